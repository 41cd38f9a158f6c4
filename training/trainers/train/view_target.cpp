#include "s4d/train/view_target.h"

#include <span>
#include <utility>

namespace s4d::train {

ViewTarget::ViewTarget(engine::Context& ctx, std::string name) : ctx_(&ctx), name_(std::move(name)) {}

splat::Camera ViewTarget::load(const data::View& view, data::FrameCache& frames) {
  const io::ImageF& image = frames.get(view);
  const splat::Camera cam = splat::to_splat_camera(view.camera);
  const size_t n = size_t{cam.width} * cam.height * 3;
  if (target_.size() < n * 4) {
    target_ = engine::Buffer(*ctx_, name_ + " target", n * 4);
    v_rgb_ = engine::Buffer(*ctx_, name_ + " image gradient", n * 4);
  }
  ctx_->upload(target_, std::span<const float>(image.data));
  return cam;
}

}  // namespace s4d::train
