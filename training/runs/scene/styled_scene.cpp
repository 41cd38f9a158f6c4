#include "s4d/scene/styled_scene.h"

#include <span>
#include <stdexcept>

#include "s4d/engine/buffer_from.h"
#include "s4d/primitives/add.h"

namespace s4d::scene {

splat::GaussianParams record_style_deltas(engine::Recorder& rec, const splat::GaussianParams& g,
                                          const engine::Buffer& sh_delta, const engine::Buffer& opacity_delta,
                                          const engine::Buffer& out_sh, const engine::Buffer& out_opacity) {
  using splat::Attr;
  if (g[Attr::sh] == nullptr || g[Attr::opacity_logits] == nullptr || g[Attr::colors] != nullptr)
    throw std::invalid_argument("a style applies to SH colours and opacities; this scene has none");
  const uint32_t sh_floats = g.count * g.sh_coeffs * 3;
  rec.copy(*g[Attr::sh], out_sh, size_t{sh_floats} * 4);
  rec.copy(*g[Attr::opacity_logits], out_opacity, size_t{g.count} * 4);
  rec.barrier();
  primitives::cmd_add(rec, out_sh, sh_delta, sh_floats);
  primitives::cmd_add(rec, out_opacity, opacity_delta, g.count);
  splat::GaussianParams out = g;
  out[Attr::sh] = &out_sh;
  out[Attr::opacity_logits] = &out_opacity;
  return out;
}

splat::StyleMlp style_mlp(double time, run::DepthInput depth, float depth_scale,
                          bool input_sigmoid) {
  splat::StyleMlp m;
  m.time = static_cast<float>(time);
  m.depth = depth == run::DepthInput::ndc ? splat::StyleDepth::ndc : splat::StyleDepth::relative;
  m.depth_scale = depth_scale;
  m.input_sigmoid = input_sigmoid;
  return m;
}

StyledScene::StyledScene(engine::Context& ctx, std::unique_ptr<SceneSource> base, const run::StyleFile& style, std::string name)
    : ctx_(&ctx), base_(std::move(base)), name_(std::move(name)), method_(style.method), sh_coeffs_(style.sh_coeffs),
      depth_(style.depth_input), depth_scale_(style.depth_scale), input_sigmoid_(style.input_sigmoid) {
  if (style.method == run::StyleMethod::scratch) throw std::invalid_argument("style " + name_ + " is a retrained run, not a style of this one");
  if (style.count != base_->size())
    throw std::invalid_argument("style " + name_ + " was trained for " + std::to_string(style.count) +
                                " Gaussians; the run has " + std::to_string(base_->size()) + " (was it retrained since?)");
  sh_delta_ = engine::buffer_from(ctx, name_ + " sh delta", style.sh_delta);
  opacity_delta_ = engine::buffer_from(ctx, name_ + " opacity delta", style.opacity_delta);
  sh_ = engine::Buffer(ctx, name_ + " sh", style.sh_delta.size() * 4);
  opacity_ = engine::Buffer(ctx, name_ + " opacity", style.opacity_delta.size() * 4);
  if (!style.mlp.empty()) mlp_ = engine::buffer_from(ctx, name_ + " mlp", style.mlp);
}

void StyledScene::restyle(const run::StyleFile& style) {
  if (style.method != method_ || style.count != base_->size() || style.sh_coeffs != sh_coeffs_)
    throw std::invalid_argument("style " + name_ + ": a restyle must keep the method, Gaussian count and SH layout");
  ctx_->upload(sh_delta_, std::span<const float>(style.sh_delta));
  ctx_->upload(opacity_delta_, std::span<const float>(style.opacity_delta));
  if (!style.mlp.empty()) ctx_->upload(mlp_, std::span<const float>(style.mlp));
  depth_ = style.depth_input;
  depth_scale_ = style.depth_scale;
  input_sigmoid_ = style.input_sigmoid;
}

splat::GaussianParams StyledScene::at(double time, const splat::Camera& camera) {
  return record_and_run(*ctx_, time, camera);
}

splat::GaussianParams StyledScene::record(engine::Recorder& rec, double time, const splat::Camera& camera) {
  const splat::GaussianParams g = base_->record(rec, time, camera);
  if (g.sh_coeffs != sh_coeffs_)
    throw std::invalid_argument("style " + name_ + " stores " + std::to_string(sh_coeffs_) +
                                " SH coefficients per channel; the run renders with " + std::to_string(g.sh_coeffs));
  rec.barrier();  // the base's work, if any, before the copies read it
  splat::GaussianParams out = record_style_deltas(rec, g, sh_delta_, opacity_delta_, sh_, opacity_);
  if (method_ == run::StyleMethod::full) {
    mlp_desc_ = style_mlp(time, depth_, depth_scale_, input_sigmoid_);
    out.style = &mlp_desc_;
    out[splat::Attr::style_mlp] = &mlp_;
  }
  return out;
}

std::string StyledScene::describe() const {
  return "style " + name_ + " (" + run::method_name(method_) + ") over " + base_->describe();
}

}  // namespace s4d::scene
