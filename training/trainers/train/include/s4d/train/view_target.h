// A view's frame on the device, and the buffer its loss gradient goes to: what every trainer's step
// (the scene's stages 1 and 2, the style's stage 4) and the evaluator upload before they render.
// Both buffers grow to the largest view so far and are reused.
#pragma once
#include <string>

#include "s4d/data/dataset.h"
#include "s4d/data/frame_cache.h"
#include "s4d/engine/buffer.h"
#include "s4d/engine/context.h"
#include "s4d/splat/rasterizer.h"
#include "s4d/splat/scene_upload.h"

namespace s4d::train {

class ViewTarget {
 public:
  // Buffers named "NAME target" and "NAME image gradient".
  ViewTarget(engine::Context& ctx, std::string name);

  // Uploads `view`'s frame (RGB, from `frames`); returns the view's camera.
  splat::Camera load(const data::View& view, data::FrameCache& frames);
  const engine::Buffer& image() const { return target_; }
  // The loss writes d loss / d pixel here; the rasterizer's backward reads it.
  engine::Buffer& image_gradient() { return v_rgb_; }

 private:
  engine::Context* ctx_;
  std::string name_;
  engine::Buffer target_, v_rgb_;
};

}  // namespace s4d::train
