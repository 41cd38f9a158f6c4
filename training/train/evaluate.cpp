#include "s4d/train/evaluate.h"

#include <algorithm>

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

Evaluator::Evaluator(engine::Context& ctx) : ctx_(&ctx), loss_(ctx, "evaluation ssim") {}

Evaluation Evaluator::evaluate(splat::Rasterizer& rast, const ParamsAt& params_at,
                               const std::vector<const data::View*>& views, data::FrameCache& frames,
                               const std::array<float, 3>& background, const std::filesystem::path& save_dir) {
  Evaluation out;
  if (!save_dir.empty()) std::filesystem::create_directories(save_dir);
  for (const data::View* view : views) {
    const io::ImageF& target = frames.get(*view);
    const splat::Camera cam = splat::to_splat_camera(view->camera);
    rast.forward(params_at(*view), cam, background);
    const size_t n = size_t{cam.width} * cam.height * 3;
    io::ImageF image{int(cam.width), int(cam.height), 3, ctx_->download<float>(rast.rgb(), n)};
    for (float& v : image.data) v = std::clamp(v, 0.0f, 1.0f);  // 3DGS scores the clamped render
    if (image_.size() < n * 4) {
      image_ = engine::Buffer(*ctx_, "evaluation image", n * 4);
      target_ = engine::Buffer(*ctx_, "evaluation target", n * 4);
      grad_ = engine::Buffer(*ctx_, "evaluation gradient", n * 4);
    }
    ctx_->upload(image_, std::span<const float>(image.data));
    ctx_->upload(target_, std::span<const float>(target.data));
    engine::Recorder rec(*ctx_, "evaluation ssim");
    loss_.record(rec, image_, target_, cam.width, cam.height, 3, 1.0f, grad_);
    ctx_->run(std::move(rec));
    ViewScore score{view->name, view->time, io::psnr(image, target), loss_.value().ssim};
    out.psnr += score.psnr;
    out.ssim += score.ssim;
    if (!save_dir.empty()) {
      std::string file = view->name;
      std::replace(file.begin(), file.end(), '/', '_');
      io::write_png(save_dir / (file + ".png"), image);
    }
    out.views.push_back(std::move(score));
  }
  if (!views.empty()) out.psnr /= double(views.size()), out.ssim /= double(views.size());
  return out;
}

}  // namespace s4d::train
