#include "s4d/scene/styled_scene.h"

#include <span>
#include <stdexcept>

#include "s4d/engine/buffer_from.h"
#include "s4d/io/half_float.h"
#include "s4d/splat/scene_upload.h"
#include "s4d/primitives/add.h"

namespace s4d::scene {

namespace {

// out = g[a] + delta, g's buffer copied to `out` and the delta added, after a barrier.
void record_delta(engine::Recorder& rec, splat::GaussianParams& g, splat::Attr a, const engine::Buffer& delta,
                  const engine::Buffer& out) {
  const uint32_t floats = g.count * splat::attr_floats(a, g.sh_coeffs);
  rec.copy(*g[a], out, size_t{floats} * 4);
  rec.barrier();
  primitives::cmd_add(rec, out, delta, floats);
  g[a] = &out;
}

void check_styleable(const splat::GaussianParams& g) {
  using splat::Attr;
  if (g[Attr::sh] == nullptr || g[Attr::opacity_logits] == nullptr || g[Attr::colors] != nullptr)
    throw std::invalid_argument("a style applies to SH colours and opacities; this scene has none");
}

}  // namespace

splat::GaussianParams record_style_deltas(engine::Recorder& rec, const splat::GaussianParams& g,
                                          const engine::Buffer& sh_delta, const engine::Buffer& opacity_delta,
                                          const engine::Buffer& out_sh, const engine::Buffer& out_opacity) {
  check_styleable(g);
  if (g.sh_storage != splat::Storage::f32)
    throw std::invalid_argument("a style's SH delta is added to float SH; these are packed halves");
  splat::GaussianParams out = g;
  record_delta(rec, out, splat::Attr::sh, sh_delta, out_sh);
  record_delta(rec, out, splat::Attr::opacity_logits, opacity_delta, out_opacity);
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

StyledScene::StyledScene(engine::Context& ctx, std::unique_ptr<SceneSource> base, const run::StyleFile& style, std::string name,
                         splat::Storage storage)
    : ctx_(&ctx), base_(std::move(base)), name_(std::move(name)), method_(style.method), sh_coeffs_(style.sh_coeffs),
      depth_(style.depth_input), depth_scale_(style.depth_scale), input_sigmoid_(style.input_sigmoid), storage_(storage) {
  if (style.method == run::StyleMethod::scratch) throw std::invalid_argument("style " + name_ + " is a retrained run, not a style of this one");
  if (style.count != base_->size())
    throw std::invalid_argument("style " + name_ + " was trained for " + std::to_string(style.count) +
                                " Gaussians; the run has " + std::to_string(base_->size()) + " (was it retrained since?)");
  if (storage == splat::Storage::f16) {
    const splat::GaussianParams g = base_->at(0.0, {});
    if (g.sh_storage == splat::Storage::f16) {  // the base's SH are the same at every time
      check_sh_layout(g);
      base_sh_ = io::unpack_halves(ctx.download<uint32_t>(*g[splat::Attr::sh], g.bytes(splat::Attr::sh) / 4),
                                   style.sh_delta.size());
    }
  }
  upload_sh(style);
  opacity_delta_ = engine::buffer_from(ctx, name_ + " opacity delta", style.opacity_delta);
  opacity_ = engine::Buffer(ctx, name_ + " opacity", style.opacity_delta.size() * 4);
  if (!style.mlp.empty()) mlp_ = splat::upload_as(ctx, name_ + " mlp", style.mlp, storage_);
}

void StyledScene::check_sh_layout(const splat::GaussianParams& g) const {
  check_styleable(g);
  if (g.sh_coeffs != sh_coeffs_)
    throw std::invalid_argument("style " + name_ + " stores " + std::to_string(sh_coeffs_) +
                                " SH coefficients per channel; the run renders with " + std::to_string(g.sh_coeffs));
}

void StyledScene::upload_sh(const run::StyleFile& style) {
  if (!base_sh_.empty()) {  // the styled SH, added in float and packed once
    std::vector<float> sh = base_sh_;
    for (size_t j = 0; j < sh.size(); ++j) sh[j] += style.sh_delta[j];
    if (sh_.valid()) splat::upload_into(*ctx_, sh_, sh, splat::Storage::f16);
    else sh_ = splat::upload_as(*ctx_, name_ + " sh", sh, splat::Storage::f16);
  } else if (sh_delta_.valid()) {
    ctx_->upload(sh_delta_, std::span<const float>(style.sh_delta));
  } else {
    sh_delta_ = engine::buffer_from(*ctx_, name_ + " sh delta", style.sh_delta);
    sh_ = engine::Buffer(*ctx_, name_ + " sh", style.sh_delta.size() * 4);
  }
}

void StyledScene::restyle(const run::StyleFile& style) {
  if (style.method != method_ || style.count != base_->size() || style.sh_coeffs != sh_coeffs_)
    throw std::invalid_argument("style " + name_ + ": a restyle must keep the method, Gaussian count and SH layout");
  upload_sh(style);
  ctx_->upload(opacity_delta_, std::span<const float>(style.opacity_delta));
  if (!style.mlp.empty()) splat::upload_into(*ctx_, mlp_, style.mlp, storage_);
  depth_ = style.depth_input;
  depth_scale_ = style.depth_scale;
  input_sigmoid_ = style.input_sigmoid;
}

splat::GaussianParams StyledScene::at(double time, const splat::Camera& camera) {
  return record_and_run(*ctx_, time, camera);
}

splat::GaussianParams StyledScene::record(engine::Recorder& rec, double time, const splat::Camera& camera) {
  const splat::GaussianParams g = base_->record(rec, time, camera);
  check_sh_layout(g);
  rec.barrier();  // the base's work, if any, before the copies read it
  splat::GaussianParams out = g;
  if (base_sh_.empty()) {
    out = record_style_deltas(rec, g, sh_delta_, opacity_delta_, sh_, opacity_);
  } else {  // sh_ holds the styled SH already
    record_delta(rec, out, splat::Attr::opacity_logits, opacity_delta_, opacity_);
    out[splat::Attr::sh] = &sh_;
  }
  if (method_ == run::StyleMethod::full) {
    mlp_desc_ = style_mlp(time, depth_, depth_scale_, input_sigmoid_);
    out.style = &mlp_desc_;
    out[splat::Attr::style_mlp] = &mlp_;
    out.style_mlp_storage = storage_;
  }
  return out;
}

size_t StyledScene::sh_style_bytes() const {
  return base_->sh_style_bytes() + sh_delta_.size() + sh_.size() + mlp_.size();
}

std::string StyledScene::describe() const {
  return "style " + name_ + " (" + run::method_name(method_) + ") over " + base_->describe();
}

}  // namespace s4d::scene
