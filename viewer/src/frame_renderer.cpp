#include "s4d/viewer/frame_renderer.h"

#include "s4d/primitives/shader_pipeline.h"
#include "s4d_viewer.h"

namespace s4d::viewer {

FrameRenderer::FrameRenderer(engine::Context& ctx, const std::array<float, 3>& background)
    : ctx_(&ctx), background_(background), rasterizer_(ctx, "viewer rasterizer") {}

splat::RenderStats FrameRenderer::render(scene::SceneSource& source, const splat::Camera& cam, double time,
                                         PixelOrder order, engine::Recorder& rec) {
  const splat::RenderStats stats = rasterizer_.forward(source.at(time, cam), cam, background_);
  const uint32_t pixels = cam.width * cam.height;
  if (pixels_.size() < size_t{pixels} * 4) pixels_ = engine::Buffer(*ctx_, "viewer pixels", size_t{pixels} * 4);
  width_ = cam.width, height_ = cam.height, order_ = order;
  const gpu::PackParams params{.pixels = pixels, .swap_rb = order == PixelOrder::bgra ? 1u : 0u, ._pad0 = 0, ._pad1 = 0};
  rec.begin_label("present_pack");
  rec.dispatch(primitives::shader_pipeline(*ctx_, shaders::Id::present_pack),
               {S4D_BIND(PACK_RGB, rasterizer_.rgb(), 0, size_t{pixels} * 12),
                S4D_BIND(PACK_PIXELS, pixels_, 0, size_t{pixels} * 4)},
               params, primitives::ceil_div(pixels, S4D_PACK_WG));
  rec.end_label();
  return stats;
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
