// DeformationField: recording of deform_feat, deform_fwd, deform_cot, deform_bwd, deform_feat_bwd + deform_wgrad (or
// the _cas variants) and deform_reg, with the host-side checks that run before anything is recorded.
#include <algorithm>
#include <stdexcept>
#include <string>

#include "s4d/deform/deformation_field.h"
#include "s4d/primitives/shader_pipeline.h"

namespace s4d::deform {

namespace {

using primitives::ceil_div;
using primitives::shader_pipeline;

// llvmpipe ends a shader invocation after 65535 loop iterations in total and says nothing (Mesa
// 22.3, docs/rasterizer.md "lavapipe caveat"). An upper bound of any deform kernel's iterations per
// invocation at the shape limits of s4d_deform.h: deform_bwd sums over at most the five heads' W
// outputs; deform_feat_bwd visits per level and plane each channel's other five planes and four
// atomics (one compare-and-swap try each when uncontended); the layout walks of s4d_deform.h
// (plane offsets, head and layer tables) stay under 2000. The MLP's size beyond one layer does not
// enters: no field within the limits comes near the budget.
constexpr uint64_t kLoopBudget = 65535;
constexpr uint64_t kLoopBound =
    std::max<uint64_t>(uint64_t{S4D_DEFORM_HEADS} * S4D_DEFORM_MAX_WIDTH,
                       uint64_t{S4D_DEFORM_MAX_LEVELS} * S4D_DEFORM_PLANES * S4D_DEFORM_MAX_CHANNELS * (S4D_DEFORM_PLANES + 4)) +
    2000;
static_assert(kLoopBound < kLoopBudget / 4,  // a quarter: margin for the estimate
              "raising S4D_DEFORM_MAX_* brings the deform kernels near llvmpipe's 65535 loop iterations per invocation");

// deform_feat_bwd specialised to this field's C (its private samples' capacity).
const engine::Pipeline& sized_pipeline(engine::Context& ctx, shaders::Id id, const gpu::DeformShape& s) {
  const shaders::Entry& e = shaders::get(id);
  return ctx.pipeline(e.name, e.spirv(), {{S4D_DEFORM_SPEC_CHANNELS, s.channels}});
}

void require(const engine::Buffer* b, const char* what, size_t bytes, const std::string& name) {
  if (b == nullptr) throw std::invalid_argument(name + ": buffer '" + what + "' is required");
  if (b->size() < bytes)
    throw std::invalid_argument(name + ": buffer '" + what + "' (" + b->name() + ") holds " + std::to_string(b->size()) +
                                " bytes, needs " + std::to_string(bytes));
}

using splat::Attr;

// Floats per Gaussian of head h's parameter.
size_t head_floats(uint32_t h, uint32_t sh_coeffs) { return splat::attr_floats(splat::kCloudAttrs[h], sh_coeffs); }

// Bytes of the canonical parameter head h reads (the SH may be packed halves).
size_t head_input_bytes(uint32_t h, const CanonicalGaussians& g) {
  const splat::Storage s = splat::kCloudAttrs[h] == Attr::sh ? g.sh_storage : splat::Storage::f32;
  return splat::attr_bytes(splat::kCloudAttrs[h], g.sh_coeffs, g.count, s);
}

const char* head_name(uint32_t h) { return splat::attr_name(splat::kCloudAttrs[h]); }

}  // namespace

void DeformationField::check_gaussians(const CanonicalGaussians& g) const {
  const size_t n = g.count;
  if (gpu::deform_head_on(shape_, 4) && g.sh_coeffs != S4D_DEFORM_SH_COEFFS)
    throw std::invalid_argument(name_ + ": the sh head needs sh_coeffs = 16, got " + std::to_string(g.sh_coeffs));
  require(g[Attr::means], "means", n * 12, name_);
  for (uint32_t h = 0; h < S4D_DEFORM_HEADS; ++h)
    if (gpu::deform_head_on(shape_, h))
      require(g[splat::kCloudAttrs[h]], head_name(h), head_input_bytes(h, g), name_);
  if (g.still_count > g.count)
    throw std::invalid_argument(name_ + ": " + std::to_string(g.still_count) + " still Gaussians of " +
                                std::to_string(g.count));
}

gpu::DeformParams DeformationField::params(const CanonicalGaussians& g, float time) const {
  const std::array<float, 3> scale = aabb_scale(config_);
  gpu::DeformParams p{};
  p.shape = shape_;
  p.aabb_max = {config_.aabb_max[0], config_.aabb_max[1], config_.aabb_max[2], 0.0f};
  p.aabb_scale = {scale[0], scale[1], scale[2], 0.0f};
  p.n = g.count - g.still_count;
  p.sh_coeffs = g.sh_coeffs;
  p.time = grid_time(config_, time);
  return p;
}

void DeformationField::record_zero_grads(engine::Recorder& rec) const {
  rec.fill(v_planes_, 0);
  rec.fill(v_mlp_, 0);
}

uint32_t DeformationField::heads_on() const { return (gpu::deform_layer_count(shape_) - shape_.trunk_extra - 1) / 2; }

// The MLP's forward over one pass's rows, after deform_feat: the trunk layers, the heads' hidden
// layers and, with `outputs`, their output layers, each set one deform_fwd dispatch after a barrier.
void DeformationField::record_mlp_forward(engine::Recorder& rec, gpu::DeformParams p, const CanonicalGaussians& g,
                                          const splat::GaussianBuffers<engine::Buffer>* outputs) const {
  auto in = [&](const engine::Buffer* b) -> const engine::Buffer& { return b ? *b : *g[Attr::means]; };
  auto out = [&](Attr a) -> const engine::Buffer& { return in(outputs ? (*outputs)[a] : nullptr); };
  const bool sh_half = g.sh_storage == splat::Storage::f16;
  const engine::Pipeline& fwd = shader_pipeline(*ctx_, sh_half ? shaders::Id::deform_fwd_half : shaders::Id::deform_fwd);
  const uint32_t tiles = ceil_div(p.n - p.first, S4D_DEFORM_TILE), te = shape_.trunk_extra;
  auto set = [&](uint32_t layer, uint32_t layers) {
    p.layer = layer;
    p.layers = layers;
    rec.barrier();
    // Bindings of heads that are off, or of sets that write no output, are never accessed; the means stand in.
    rec.dispatch(fwd,
                 {S4D_BIND(DFWD_MLP, mlp_), S4D_BIND(DFWD_SCRATCH, scratch_), S4D_BIND(DFWD_MEANS, *g[Attr::means]),
                  S4D_BIND(DFWD_LOG_SCALES, in(g[Attr::log_scales])), S4D_BIND(DFWD_QUATS, in(g[Attr::quats])),
                  S4D_BIND(DFWD_OPACITY_LOGITS, in(g[Attr::opacity_logits])), S4D_BIND(DFWD_SH, in(g[Attr::sh])),
                  S4D_BIND(DFWD_OUT_MEANS, out(Attr::means)), S4D_BIND(DFWD_OUT_LOG_SCALES, out(Attr::log_scales)),
                  S4D_BIND(DFWD_OUT_QUATS, out(Attr::quats)), S4D_BIND(DFWD_OUT_OPACITY_LOGITS, out(Attr::opacity_logits)),
                  S4D_BIND(DFWD_OUT_SH, out(Attr::sh))},
                 p, tiles * gpu::deform_set_blocks(shape_, layer, layers, false, false));
  };
  for (uint32_t e = 0; e <= te; ++e) set(e, 1);
  set(te + 1, heads_on());
  if (outputs) set(te + 2, heads_on());
}

void DeformationField::record_forward(engine::Recorder& rec, const CanonicalGaussians& g, float time,
                                      const splat::GaussianBuffers<engine::Buffer>& out) const {
  check_gaussians(g);
  for (uint32_t h = 0; h < S4D_DEFORM_HEADS; ++h)
    if (gpu::deform_head_on(shape_, h))
      require(out[splat::kCloudAttrs[h]], (std::string("deformed ") + head_name(h)).c_str(),
              size_t{g.count} * head_floats(h, g.sh_coeffs) * 4, name_);
  const uint32_t moving = g.count - g.still_count, rows = scratch_rows();
  rec.begin_label(name_ + " deform forward");
  for (uint32_t first = 0; first < moving; first += rows) {
    gpu::DeformParams p = params(g, time);
    p.first = first;
    p.n = std::min(moving - first, rows) + first;
    rec.barrier();  // the scratch's previous readers are done
    rec.dispatch(shader_pipeline(*ctx_, shaders::Id::deform_feat),
                 {S4D_BIND(DFEAT_PLANES, planes_), S4D_BIND(DFEAT_MEANS, *g[Attr::means]), S4D_BIND(DFEAT_SCRATCH, scratch_)}, p,
                 ceil_div(p.n - first, S4D_DEFORM_WG));
    record_mlp_forward(rec, p, g, &out);
  }
  for (uint32_t h = 0; h < S4D_DEFORM_HEADS; ++h)
    if (gpu::deform_head_on(shape_, h) && g.still_count > 0) {  // still: deformed = canonical
      const size_t row = head_floats(h, g.sh_coeffs) * 4;
      const Attr a = splat::kCloudAttrs[h];
      rec.copy(*g[a], *out[a], g.still_count * row, moving * row, moving * row);
    }
  rec.end_label();
}

void DeformationField::record_backward(engine::Recorder& rec, const CanonicalGaussians& g, float time,
                                       const splat::GaussianGrads& v) const {
  check_gaussians(g);
  if (g.sh_storage != splat::Storage::f32)
    throw std::invalid_argument(name_ + ": the backward needs float SH; halves are a trained model's render-side storage");
  require(v[Attr::means], "v_means", size_t{g.count} * 12, name_);
  for (uint32_t h = 1; h < S4D_DEFORM_HEADS; ++h)
    if (gpu::deform_head_on(shape_, h))
      require(v[splat::kCloudAttrs[h]], (std::string("v_") + head_name(h)).c_str(),
              size_t{g.count} * head_floats(h, g.sh_coeffs) * 4, name_);
  const engine::DeviceInfo& info = ctx_->info();
  const bool float_atomics = info.float_atomic_add_buffer && info.float_atomic_add_shared && !options_.force_cas_atomics;
  const uint32_t moving = g.count - g.still_count;
  if (moving == 0) return;
  auto in = [&](const engine::Buffer* b) -> const engine::Buffer& { return b ? *b : *g[Attr::means]; };
  const uint32_t rows = scratch_rows(), te = shape_.trunk_extra;
  gpu::DeformWgradParams wp{};
  wp.shape = shape_;
  wp.row_floats = gpu::deform_scratch_floats(shape_);
  wp.blocks = gpu::deform_wgrad_blocks(shape_);
  const engine::Pipeline& bwd = shader_pipeline(*ctx_, shaders::Id::deform_bwd);
  const engine::Pipeline& feat_bwd =
      sized_pipeline(*ctx_, float_atomics ? shaders::Id::deform_feat_bwd : shaders::Id::deform_feat_bwd_cas, shape_);
  const engine::Pipeline& wgrad =
      shader_pipeline(*ctx_, float_atomics ? shaders::Id::deform_wgrad : shaders::Id::deform_wgrad_cas);
  rec.begin_label(name_ + (float_atomics ? " deform backward" : " deform backward (cas)"));
  for (uint32_t first = 0; first < moving; first += rows) {
    gpu::DeformParams p = params(g, time);
    p.first = first;
    p.n = std::min(moving - first, rows) + first;
    wp.rows = p.n - first;
    const uint32_t groups = ceil_div(wp.rows, S4D_DEFORM_WG), tiles = ceil_div(wp.rows, S4D_DEFORM_TILE);
    rec.barrier();  // the scratch's previous readers are done
    rec.dispatch(shader_pipeline(*ctx_, shaders::Id::deform_feat),
                 {S4D_BIND(DFEAT_PLANES, planes_), S4D_BIND(DFEAT_MEANS, *g[Attr::means]), S4D_BIND(DFEAT_SCRATCH, scratch_)}, p,
                 groups);
    rec.dispatch(shader_pipeline(*ctx_, shaders::Id::deform_cot),
                 {S4D_BIND(DCOT_V_MEANS, *v[Attr::means]), S4D_BIND(DCOT_V_LOG_SCALES, in(v[Attr::log_scales])),
                  S4D_BIND(DCOT_V_QUATS, in(v[Attr::quats])), S4D_BIND(DCOT_V_OPACITY_LOGITS, in(v[Attr::opacity_logits])),
                  S4D_BIND(DCOT_V_SH, in(v[Attr::sh])), S4D_BIND(DCOT_SCRATCH, scratch_)},
                 p, groups);
    record_mlp_forward(rec, p, g, nullptr);  // the activations: nothing is kept from the forward
    // Input cotangents, from the heads' outputs back to the features.
    auto set = [&](uint32_t layer, uint32_t layers, bool shared_input) {
      p.layer = layer;
      p.layers = layers;
      p.shared_input = shared_input ? 1 : 0;
      rec.barrier();
      rec.dispatch(bwd, {S4D_BIND(DBWD_MLP, mlp_), S4D_BIND(DBWD_SCRATCH, scratch_)}, p, tiles * gpu::deform_set_blocks(shape_, layer, layers, true, shared_input));
    };
    set(te + 2, heads_on(), false);
    set(te + 1, heads_on(), true);
    for (uint32_t e = te + 1; e-- > 0;) set(e, 1, false);
    rec.barrier();
    rec.dispatch(feat_bwd,
                 {S4D_BIND(DFB_PLANES, planes_), S4D_BIND(DFB_MEANS, *g[Attr::means]), S4D_BIND(DFB_V_MEANS, *v[Attr::means]),
                  S4D_BIND(DFB_V_PLANES, v_planes_), S4D_BIND(DFB_SCRATCH, scratch_)},
                 p, groups);
    rec.dispatch(wgrad, {S4D_BIND(DWG_SCRATCH, scratch_), S4D_BIND(DWG_V_MLP, v_mlp_)}, wp,
                 ceil_div(uint64_t{ceil_div(wp.rows, S4D_DEFORM_WGRAD_ROWS)} * wp.blocks, S4D_DEFORM_WGRAD_WG));
  }
  rec.barrier();
  rec.end_label();
}

void DeformationField::record_regularisers(engine::Recorder& rec, const RegulariserWeights& w) const {
  gpu::DeformRegParams p{};
  p.shape = shape_;
  p.elements = plane_floats();
  p.w_plane_tv = w.plane_tv;
  p.w_time_smoothness = w.time_smoothness;
  p.w_l1_time = w.l1_time_planes;
  rec.begin_label(name_ + " deform_reg");
  rec.dispatch(shader_pipeline(*ctx_, shaders::Id::deform_reg),
               {S4D_BIND(DREG_PLANES, planes_), S4D_BIND(DREG_V_PLANES, v_planes_), S4D_BIND(DREG_PARTIALS, reg_partials_)}, p,
               ceil_div(p.elements, S4D_DEFORM_REG_WG));
  rec.end_label();
}

}  // namespace s4d::deform
