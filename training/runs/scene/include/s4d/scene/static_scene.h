// The static stage's scene: one Gaussian cloud, the same at every time.
#pragma once
#include <string>

#include "s4d/engine/context.h"
#include "s4d/io/ply_gaussians.h"
#include "s4d/scene/scene_source.h"
#include "s4d/splat/scene_upload.h"

namespace s4d::scene {

class StaticScene final : public SceneSource {
 public:
  // Uploads `cloud`, its SH as `sh_storage` (f16: packed halves, for rendering); renders at SH
  // degree `sh_degree` (clamped to what the cloud stores; negative: every degree it stores).
  StaticScene(engine::Context& ctx, const io::GaussianCloud& cloud, int sh_degree = -1,
              const std::string& name = "static scene", splat::Storage sh_storage = splat::Storage::f32);

  splat::GaussianParams record(engine::Recorder&, double time, const splat::Camera& camera) override {
    return at(time, camera);  // nothing to compute
  }
  splat::GaussianParams at(double time, const splat::Camera& camera) override;
  uint32_t size() const override { return gaussians_.size(); }
  bool dynamic() const override { return false; }
  std::string describe() const override;
  size_t sh_style_bytes() const override { return gaussians_.sh_bytes(); }

 private:
  splat::DeviceGaussians gaussians_;
  int sh_degree_;
};

}  // namespace s4d::scene
