// One viewer frame: a scene source's Gaussians at a time through the compute rasterizer,
// then the float image packed into 8-bit pixels on the device (shaders/viewer/present_pack.comp).
// The window copies pixels() into its swapchain image; captures and screenshots read them back
// once. Every path that shows or saves a frame goes through render().
#pragma once
#include <array>
#include <cstdint>

#include "s4d/engine/buffer.h"
#include "s4d/engine/context.h"
#include "s4d/engine/recorder.h"
#include "s4d/io/image_io.h"
#include "s4d/scene/scene_source.h"
#include "s4d/splat/rasterizer.h"

namespace s4d::viewer {

enum class PixelOrder { rgba, bgra };  // byte order of pixels() in memory

class FrameRenderer {
 public:
  FrameRenderer(engine::Context& ctx, const std::array<float, 3>& background);

  // Rasterizes source.at(time, cam) (forward() submits and waits) and records the packing into
  // `rec`; pixels() holds the frame once `rec` has run.
  splat::RenderStats render(scene::SceneSource& source, const splat::Camera& cam, double time, PixelOrder order,
                            engine::Recorder& rec);

  // [height * width] u32 of the last render, row-major, one byte per channel, alpha 255.
  const engine::Buffer& pixels() const { return pixels_; }
  uint32_t width() const { return width_; }
  uint32_t height() const { return height_; }
  // The last frame as an 8-bit-exact RGB image (values level / 255). Reads back from the device:
  // for captures and screenshots, never for every frame.
  io::ImageF read_rgb() const;

 private:
  engine::Context* ctx_;
  std::array<float, 3> background_;
  splat::Rasterizer rasterizer_;
  engine::Buffer pixels_;
  uint32_t width_ = 0, height_ = 0;
  PixelOrder order_ = PixelOrder::rgba;
};

}  // namespace s4d::viewer
