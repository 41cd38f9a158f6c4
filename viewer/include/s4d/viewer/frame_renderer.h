// One viewer frame: a scene source's Gaussians at a time through the compute rasterizer,
// then the float image packed into 8-bit pixels on the device (shaders/viewer/present_pack.comp).
// A frame may be rasterized at a fraction of the window's size (the viewer does while the view
// moves, adaptive_resolution.h); the pack upsamples it to the full size.
// The window copies pixels() into its swapchain image; captures and screenshots read them back
// once. Every path that shows or saves a frame goes through render(), which records the scene
// source's work, the rasterizer and the pack into the caller's command buffer: with the window's
// copy and panel, one submission per frame.
#pragma once
#include <array>
#include <cstdint>
#include <optional>

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

  // Records source.record(time, scaled_camera(cam, scale)), its rasterization and the packing to
  // cam's full size into `rec`; pixels() holds the frame once `rec` has run and finish() returned
  // stats. At scale 1 the pixels are the unscaled render's, bit for bit.
  void render(scene::SceneSource& source, const splat::Camera& cam, double time, PixelOrder order,
              engine::Recorder& rec, double scale = 1);
  // After the rendered frame ran: its stats, or nullopt when the rasterizer's instance buffers
  // overflowed (grown now; render the frame again).
  std::optional<splat::RenderStats> finish();
  // render() in a submission of its own, waited for and finished; again after an overflow.
  splat::RenderStats render_now(scene::SceneSource& source, const splat::Camera& cam, double time, PixelOrder order,
                                double scale = 1);
  const splat::Rasterizer& rasterizer() const { return rasterizer_; }

  // [height * width] u32 of the last render, row-major, one byte per channel, alpha 255.
  const engine::Buffer& pixels() const { return pixels_; }
  uint32_t width() const { return width_; }
  uint32_t height() const { return height_; }
  double scale() const { return scale_; }  // of the last render
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
  double scale_ = 1;
};

// `cam` rendered at `scale` of its size: width and height scaled_size(), focal lengths and
// principal point scaled per axis by the ratio of the sizes, so pixel centres of the smaller image
// map onto the same rays as present_pack's upsampling assumes. Scale 1 returns cam unchanged.
splat::Camera scaled_camera(const splat::Camera& cam, double scale);

// Records present_pack: rgb [src_height*src_width*3] f32 (upsampled when smaller) into pixels
// [height*width] u32 in `order`. Throws std::invalid_argument when the source is larger than the
// output or a buffer is too small.
void record_present_pack(engine::Context& ctx, engine::Recorder& rec, const engine::Buffer& rgb, uint32_t src_width,
                         uint32_t src_height, const engine::Buffer& pixels, uint32_t width, uint32_t height,
                         PixelOrder order);

}  // namespace s4d::viewer
