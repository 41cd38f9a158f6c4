// A run's scene in the blend of two of its styles (style_blend.h): a StyledScene of the blended
// style that keeps both styles on the host, so that changing the blend factor (the viewer's slider)
// re-blends and uploads the arrays without reading any file again.
#pragma once
#include <memory>
#include <string>

#include "s4d/run/style_file.h"
#include "s4d/scene/styled_scene.h"

namespace s4d::scene {

class BlendedScene final : public SceneSource {
 public:
  // `a` and `b` are the styles' contents (no_style for the original scene), named for logs; alpha is
  // the weight on b; `storage` as StyledScene's. blend_styles' errors propagate, and StyledScene's
  // for another Gaussian count.
  BlendedScene(engine::Context& ctx, std::unique_ptr<SceneSource> base, run::StyleFile a, const std::string& name_a,
               run::StyleFile b, const std::string& name_b, float alpha, splat::Storage storage = splat::Storage::f32);

  // Re-blends with weight `alpha` on b. The device must have finished the work that reads the last
  // at()'s buffers.
  void set_alpha(float alpha);
  float alpha() const { return alpha_; }

  splat::GaussianParams record(engine::Recorder& rec, double time, const splat::Camera& camera) override {
    return styled_->record(rec, time, camera);
  }
  splat::GaussianParams at(double time, const splat::Camera& camera) override { return styled_->at(time, camera); }
  uint32_t size() const override { return styled_->size(); }
  bool dynamic() const override { return styled_->dynamic(); }
  std::string describe() const override;
  size_t sh_style_bytes() const override { return styled_->sh_style_bytes(); }

 private:
  run::StyleFile a_, b_;
  float alpha_;
  std::unique_ptr<StyledScene> styled_;
};

}  // namespace s4d::scene
