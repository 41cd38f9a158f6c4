// A run's scene in one of its trained styles: the run's own Gaussians at time t (any SceneSource)
// with the style's colour and opacity changes added and, for method "full", the per-Gaussian style
// MLPs handed to the rasterizer's fused kernels. The geometry is the run's, untouched.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "s4d/engine/buffer.h"
#include "s4d/engine/context.h"
#include "s4d/engine/recorder.h"
#include "s4d/run/style_file.h"
#include "s4d/scene/scene_source.h"

namespace s4d::scene {

// Records out_sh = g[sh] + sh_delta and out_opacity = g[opacity_logits] + opacity_delta and returns g
// pointing at the outputs: the one place where a style's deltas meet the run's values, shared by
// rendering and stage-4 training. Buffers hold g.count entries in g's layouts.
splat::GaussianParams record_style_deltas(engine::Recorder& rec, const splat::GaussianParams& g,
                                          const engine::Buffer& sh_delta, const engine::Buffer& opacity_delta,
                                          const engine::Buffer& out_sh, const engine::Buffer& out_opacity);

// The rasterizer's description of a style's MLPs at `time`; their weights, [count *
// S4D_STYLE_MLP_STRIDE], go in GaussianParams[Attr::style_mlp].
splat::StyleMlp style_mlp(double time, run::DepthInput depth, float depth_scale,
                          bool input_sigmoid);

class StyledScene final : public SceneSource {
 public:
  // Throws std::invalid_argument when the style was trained for another Gaussian count or SH layout.
  // `storage` f16 (rendering only) holds the MLPs' weights as packed halves and, where the base's SH
  // are packed halves (they do not move with time), the styled SH too: the base's SH plus the
  // delta, added once here in float and packed. Over SH the field deforms, the SH stay float.
  StyledScene(engine::Context& ctx, std::unique_ptr<SceneSource> base, const run::StyleFile& style, std::string name,
              splat::Storage storage = splat::Storage::f32);

  // Replaces the style's arrays with `style`'s (a blend of other weights, style_blend.h): the same
  // Gaussian count, SH layout and method, or std::invalid_argument. The device must have finished
  // the work that reads the last at()'s buffers.
  void restyle(const run::StyleFile& style);

  splat::GaussianParams record(engine::Recorder& rec, double time, const splat::Camera& camera) override;
  splat::GaussianParams at(double time, const splat::Camera& camera) override;
  uint32_t size() const override { return base_->size(); }
  bool dynamic() const override { return true; }  // the MLPs read the time even where nothing moves
  std::string describe() const override;
  size_t sh_style_bytes() const override;

 private:
  engine::Context* ctx_;
  std::unique_ptr<SceneSource> base_;
  std::string name_;
  run::StyleMethod method_;
  uint32_t sh_coeffs_;
  run::DepthInput depth_;
  float depth_scale_;
  bool input_sigmoid_;
  splat::Storage storage_;
  // The base's SH as floats when they are packed halves: sh_ is then these plus the delta, packed,
  // and sh_delta_ is not used.
  std::vector<float> base_sh_;
  engine::Buffer sh_delta_, opacity_delta_, mlp_, sh_, opacity_;
  splat::StyleMlp mlp_desc_{};

  void upload_sh(const run::StyleFile& style);  // sh_delta_, or sh_ when the base's SH are halves
  // Throws std::invalid_argument when g has no SH and opacities, or not the style's SH layout.
  void check_sh_layout(const splat::GaussianParams& g) const;
};

}  // namespace s4d::scene
