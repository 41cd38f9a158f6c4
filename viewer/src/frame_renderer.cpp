#include "s4d/viewer/frame_renderer.h"

#include <stdexcept>
#include <string>

#include "s4d/primitives/shader_pipeline.h"
#include "s4d/viewer/adaptive_resolution.h"
#include "s4d_viewer.h"

namespace s4d::viewer {

FrameRenderer::FrameRenderer(engine::Context& ctx, const std::array<float, 3>& background)
    : ctx_(&ctx), background_(background), rasterizer_(ctx, "viewer rasterizer") {}

splat::Camera scaled_camera(const splat::Camera& cam, double scale) {
  if (scale == 1) return cam;
  splat::Camera out = cam;
  out.width = scaled_size(cam.width, scale);
  out.height = scaled_size(cam.height, scale);
  const float sx = static_cast<float>(out.width) / static_cast<float>(cam.width);
  const float sy = static_cast<float>(out.height) / static_cast<float>(cam.height);
  out.fx = cam.fx * sx, out.cx = cam.cx * sx;
  out.fy = cam.fy * sy, out.cy = cam.cy * sy;
  return out;
}

void record_present_pack(engine::Context& ctx, engine::Recorder& rec, const engine::Buffer& rgb, uint32_t src_width,
                         uint32_t src_height, const engine::Buffer& pixels, uint32_t width, uint32_t height,
                         PixelOrder order) {
  const size_t src = size_t{src_width} * src_height, dst = size_t{width} * height;
  if (src_width == 0 || src_height == 0 || src_width > width || src_height > height)
    throw std::invalid_argument("present_pack: source " + std::to_string(src_width) + "x" +
                                std::to_string(src_height) + " must be non-empty and fit the output " +
                                std::to_string(width) + "x" + std::to_string(height));
  if (rgb.size() < src * 12 || pixels.size() < dst * 4)
    throw std::invalid_argument("present_pack: buffer '" + std::string(rgb.size() < src * 12 ? rgb.name() : pixels.name()) +
                                "' is too small for " + std::to_string(width) + "x" + std::to_string(height));
  const gpu::PackParams params{.width = width,
                               .height = height,
                               .src_width = src_width,
                               .src_height = src_height,
                               .swap_rb = order == PixelOrder::bgra ? 1u : 0u,
                               ._pad0 = 0,
                               ._pad1 = 0,
                               ._pad2 = 0};
  rec.begin_label("present_pack");
  rec.dispatch(primitives::shader_pipeline(ctx, shaders::Id::present_pack),
               {S4D_BIND(PACK_RGB, rgb, 0, src * 12), S4D_BIND(PACK_PIXELS, pixels, 0, dst * 4)}, params,
               primitives::ceil_div(dst, S4D_PACK_WG));
  rec.end_label();
}

void FrameRenderer::render(scene::SceneSource& source, const splat::Camera& cam, double time, PixelOrder order,
                           engine::Recorder& rec, double scale) {
  const splat::Camera small = scaled_camera(cam, scale);
  const splat::GaussianParams g = source.record(rec, time, small);
  rec.barrier();
  rasterizer_.record_forward(rec, g, small, background_);
  rec.barrier();
  const size_t pixels = size_t{cam.width} * cam.height;
  if (pixels_.size() < pixels * 4) pixels_ = engine::Buffer(*ctx_, "viewer pixels", pixels * 4);
  width_ = cam.width, height_ = cam.height, order_ = order, scale_ = scale;
  record_present_pack(*ctx_, rec, rasterizer_.rgb(), small.width, small.height, pixels_, cam.width, cam.height, order);
}

std::optional<splat::RenderStats> FrameRenderer::finish() { return rasterizer_.finish_forward(); }

splat::RenderStats FrameRenderer::render_now(scene::SceneSource& source, const splat::Camera& cam, double time,
                                             PixelOrder order, double scale) {
  for (;;) {  // a second time only after an overflow, which grew the rasterizer's buffers
    engine::Recorder rec(*ctx_, "viewer frame");
    render(source, cam, time, order, rec, scale);
    ctx_->run(std::move(rec));
    if (const std::optional<splat::RenderStats> stats = finish()) return *stats;
  }
}

io::ImageF FrameRenderer::read_rgb() const {
  const size_t n = size_t{width_} * height_;
  const std::vector<uint32_t> packed = ctx_->download<uint32_t>(pixels_, n);
  io::ImageF image{static_cast<int>(width_), static_cast<int>(height_), 3, std::vector<float>(3 * n)};
  const int red = order_ == PixelOrder::bgra ? 2 : 0;
  for (size_t i = 0; i < n; ++i) {
    for (int c = 0; c < 3; ++c) {
      const int shift = 8 * (c == 1 ? 1 : (c == 0 ? red : 2 - red));
      image.data[3 * i + c] = static_cast<float>((packed[i] >> shift) & 0xffu) / 255.0f;
    }
  }
  return image;
}

}  // namespace s4d::viewer
