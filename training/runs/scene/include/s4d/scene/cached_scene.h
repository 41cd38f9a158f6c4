// A scene source that computes its base's Gaussians once per listed time and keeps copies, so a
// training loop that revisits the same frame times (stage 4 over a dataset's frames) runs the
// deformation field once per time instead of once per step. Other times go to the base.
#pragma once
#include <cstddef>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "s4d/engine/buffer.h"
#include "s4d/engine/context.h"
#include "s4d/scene/scene_source.h"

namespace s4d::scene {

class CachedScene final : public SceneSource {
 public:
  // Caches every time in `times` while the copies fit in `max_bytes` (the rest stay uncached) when
  // the base is dynamic; a static base is passed through. The base must not read the camera.
  CachedScene(engine::Context& ctx, std::unique_ptr<SceneSource> base, const std::vector<double>& times, size_t max_bytes);

  splat::GaussianParams record(engine::Recorder& rec, double time, const splat::Camera& camera) override;
  splat::GaussianParams at(double time, const splat::Camera& camera) override;
  uint32_t size() const override { return base_->size(); }
  bool dynamic() const override { return base_->dynamic(); }
  std::string describe() const override;
  size_t sh_style_bytes() const override;
  size_t cached_times() const { return cache_.size(); }

 private:
  struct Copy {
    splat::PerAttr<engine::Buffer, splat::kCloudAttrCount> buffers;
    splat::GaussianParams params;
  };
  engine::Context* ctx_;
  std::unique_ptr<SceneSource> base_;
  std::map<double, Copy> cache_;
};

}  // namespace s4d::scene
