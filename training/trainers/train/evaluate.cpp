#include "s4d/train/evaluate.h"

#include <algorithm>
#include <cstdio>
#include <map>
#include <utility>

#include "s4d/io/image_io.h"
#include "s4d/io/psnr.h"
#include "s4d/splat/scene_upload.h"

namespace s4d::train {

std::vector<const data::View*> spread_views(const std::vector<const data::View*>& views, size_t k) {
  if (views.size() <= k) return views;
  std::vector<const data::View*> out;
  for (size_t i = 0; i < k; ++i) out.push_back(views[i * (views.size() - 1) / (k - 1)]);
  return out;
}

namespace {

// Views share a camera when their poses and intrinsics are equal to 1e-6 (a fixed test camera
// over time).
std::string camera_key(const io::CameraView& c) {
  std::string key;
  char buf[32];
  for (double v : c.world_to_cam) std::snprintf(buf, sizeof buf, "%.6f,", v), key += buf;
  for (double v : {c.fx, c.fy, c.cx, c.cy}) std::snprintf(buf, sizeof buf, "%.6f,", v), key += buf;
  return key + std::to_string(c.width) + "x" + std::to_string(c.height);
}

}  // namespace

Evaluator::Evaluator(engine::Context& ctx) : ctx_(&ctx), loss_(ctx, "evaluation ssim"), target_(ctx, "evaluation") {}

Evaluation Evaluator::evaluate(splat::Rasterizer& rast, const ParamsAt& params_at,
                               const std::vector<const data::View*>& views, data::FrameCache& frames,
                               const std::array<float, 3>& background, const std::filesystem::path& save_dir) {
  Evaluation out;
  if (!save_dir.empty()) std::filesystem::create_directories(save_dir);
  // Renders and ground truths by camera (the same pose and intrinsics), in time order, for the
  // moving-content score.
  std::map<std::string, std::vector<std::pair<io::ImageF, io::ImageF>>> by_camera;
  for (const data::View* view : views) {
    const io::ImageF& target = frames.get(*view);
    const splat::Camera cam = target_.load(*view, frames);
    rast.forward(params_at(*view), cam, background);
    const size_t n = size_t{cam.width} * cam.height * 3;
    io::ImageF image{int(cam.width), int(cam.height), 3, ctx_->download<float>(rast.rgb(), n)};
    for (float& v : image.data) v = std::clamp(v, 0.0f, 1.0f);  // 3DGS scores the clamped render
    if (image_.size() < n * 4) image_ = engine::Buffer(*ctx_, "evaluation image", n * 4);
    ctx_->upload(image_, std::span<const float>(image.data));
    engine::Recorder rec(*ctx_, "evaluation ssim");
    loss_.record(rec, image_, target_.image(), cam.width, cam.height, 3, 1.0f, target_.image_gradient());
    ctx_->run(std::move(rec));
    ViewScore score{view->name, view->time, io::psnr(image, target), loss_.value().ssim};
    io::ImageF empty{image.width, image.height, 3, std::vector<float>(image.data.size())};
    for (size_t i = 0; i < empty.data.size(); ++i) empty.data[i] = background[i % 3];
    out.background_psnr += io::psnr(empty, target);
    out.psnr += score.psnr;
    out.ssim += score.ssim;
    if (!save_dir.empty()) {
      std::string file = view->name;
      std::replace(file.begin(), file.end(), '/', '_');
      io::write_png(save_dir / (file + ".png"), image);
    }
    out.views.push_back(std::move(score));
    by_camera[camera_key(view->camera)].emplace_back(std::move(image), target);
  }
  io::MovingPsnr moving;
  for (const auto& [key, pairs] : by_camera) {
    std::vector<const io::ImageF*> renders, truths;
    for (const auto& [render, truth] : pairs) renders.push_back(&render), truths.push_back(&truth);
    moving.add(renders, truths);
  }
  out.moving = moving.score();
  if (!views.empty())
    out.psnr /= double(views.size()), out.ssim /= double(views.size()), out.background_psnr /= double(views.size());
  return out;
}

}  // namespace s4d::train
