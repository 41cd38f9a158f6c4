// DeformationField: recording of deform_fwd, deform_bwd + deform_wgrad (or their _cas variants) and deform_reg, with the
// host-side checks that run before anything is recorded.
#include <algorithm>
#include <stdexcept>
#include <string>

#include "s4d/deform/deformation_field.h"
#include "s4d/primitives/shader_pipeline.h"

namespace s4d::deform {

namespace {

using primitives::ceil_div;
using primitives::shader_pipeline;

// Loop iterations one invocation runs, an upper bound. Per Linear(in -> out) the forward runs
// (in + 1) out iterations (inner and outer loops together), the input cotangent (out + 1) in, so a
// pass costs at most 2 per weight: deform_fwd 1 pass, deform_bwd 2 (recomputed forward, input
// cotangent) plus the scratch row (in + out per layer) and the layer-table walks of s4d_deform.h
// (bounded by 200 per layer). The field visits, per level and plane, each channel's taps and the other
// five planes. The compare-and-swap variant loops at least once per plane atomic. deform_wgrad runs
// S4D_DEFORM_WGRAD_ROWS rows plus its layer walk, far below the limit for any shape.
// With the old in-kernel weight reduction (6 per weight) this bound was about 2x conservative: C = 4,
// 2 levels, all heads broke between W = 52 and 56 (bounds 123k, 140k).
uint64_t loop_bound(const gpu::DeformShape& s, bool backward, bool cas) {
  const uint64_t weights = gpu::deform_mlp_total(s), layers = gpu::deform_layer_count(s);
  const uint64_t field = uint64_t{s.levels} * S4D_DEFORM_PLANES * s.channels * (S4D_DEFORM_PLANES + 4);
  if (!backward) return 2 * weights + field + 1000;
  return 4 * weights + gpu::deform_scratch_floats(s) + 200 * layers + 2 * field + (cas ? field : 0) + 1000;
}

// llvmpipe ends a shader invocation after 65535 loop iterations in total and says nothing (Mesa
// 22.3, see docs/rasterizer.md "lavapipe caveat"): refuse fields whose kernels could get there.
void check_llvmpipe(const engine::DeviceInfo& info, const gpu::DeformShape& s, bool backward, bool cas,
                    const std::string& name) {
  if (info.driver_name != "llvmpipe") return;
  const uint64_t bound = loop_bound(s, backward, cas);
  if (bound > 65535)
    throw std::runtime_error(name + ": an MLP of " + std::to_string(gpu::deform_mlp_total(s)) + " floats needs up to " +
                             std::to_string(bound) + " loop iterations per Gaussian in " +
                             (backward ? "deform_bwd" : "deform_fwd") +
                             ", more than lavapipe runs correctly (65535); use a smaller width or fewer heads, or a GPU");
}

// deform_fwd / deform_bwd specialised to this field's sizes (their private arrays' capacities).
const engine::Pipeline& sized_pipeline(engine::Context& ctx, shaders::Id id, const gpu::DeformShape& s) {
  const shaders::Entry& e = shaders::get(id);
  return ctx.pipeline(e.name, e.spirv(),
                      {{S4D_DEFORM_SPEC_FEAT, gpu::deform_feat_dim(s)},
                       {S4D_DEFORM_SPEC_WIDTH, s.width},
                       {S4D_DEFORM_SPEC_TRUNK, s.trunk_extra + 1},
                       {S4D_DEFORM_SPEC_CHANNELS, s.channels}});
}

void require(const engine::Buffer* b, const char* what, size_t bytes, const std::string& name) {
  if (b == nullptr) throw std::invalid_argument(name + ": buffer '" + what + "' is required");
  if (b->size() < bytes)
    throw std::invalid_argument(name + ": buffer '" + what + "' (" + b->name() + ") holds " + std::to_string(b->size()) +
                                " bytes, needs " + std::to_string(bytes));
}

// Floats per Gaussian of head h's parameter.
size_t head_floats(uint32_t h, uint32_t sh_coeffs) { return h == 4 ? 3 * size_t{sh_coeffs} : gpu::deform_head_out(h); }

const char* const kHeadNames[S4D_DEFORM_HEADS] = {"means", "log_scales", "quats", "opacity_logits", "sh"};

}  // namespace

void DeformationField::check_gaussians(const CanonicalGaussians& g) const {
  const size_t n = g.count;
  if (gpu::deform_head_on(shape_, 4) && g.sh_coeffs != S4D_DEFORM_SH_COEFFS)
    throw std::invalid_argument(name_ + ": the sh head needs sh_coeffs = 16, got " + std::to_string(g.sh_coeffs));
  require(g.means, "means", n * 12, name_);
  const engine::Buffer* inputs[S4D_DEFORM_HEADS] = {g.means, g.log_scales, g.quats, g.opacity_logits, g.sh};
  for (uint32_t h = 0; h < S4D_DEFORM_HEADS; ++h)
    if (gpu::deform_head_on(shape_, h)) require(inputs[h], kHeadNames[h], n * head_floats(h, g.sh_coeffs) * 4, name_);
  if (g.static_count > g.count)
    throw std::invalid_argument(name_ + ": " + std::to_string(g.static_count) + " static Gaussians of " +
                                std::to_string(g.count));
}

gpu::DeformParams DeformationField::params(const CanonicalGaussians& g, float time) const {
  const std::array<float, 3> scale = aabb_scale(config_);
  gpu::DeformParams p{};
  p.shape = shape_;
  p.aabb_max = {config_.aabb_max[0], config_.aabb_max[1], config_.aabb_max[2], 0.0f};
  p.aabb_scale = {scale[0], scale[1], scale[2], 0.0f};
  p.n = g.count - g.static_count;
  p.sh_coeffs = g.sh_coeffs;
  p.time = time;
  return p;
}

void DeformationField::record_zero_grads(engine::Recorder& rec) const {
  rec.fill(v_planes_, 0);
  rec.fill(v_mlp_, 0);
}

void DeformationField::check_device() const {
  const engine::DeviceInfo& info = ctx_->info();
  const bool float_atomics = info.float_atomic_add_buffer && info.float_atomic_add_shared && !options_.force_cas_atomics;
  check_llvmpipe(info, shape_, false, false, name_);
  check_llvmpipe(info, shape_, true, !float_atomics, name_);
}

void DeformationField::record_forward(engine::Recorder& rec, const CanonicalGaussians& g, float time,
                                      const DeformedGaussians& out) const {
  check_gaussians(g);
  const engine::Buffer* outputs[S4D_DEFORM_HEADS] = {out.means, out.log_scales, out.quats, out.opacity_logits, out.sh};
  for (uint32_t h = 0; h < S4D_DEFORM_HEADS; ++h)
    if (gpu::deform_head_on(shape_, h))
      require(outputs[h], (std::string("deformed ") + kHeadNames[h]).c_str(), size_t{g.count} * head_floats(h, g.sh_coeffs) * 4, name_);
  check_llvmpipe(ctx_->info(), shape_, false, false, name_);
  // Bindings of heads that are off are never accessed; the means stand in.
  auto in = [&](const engine::Buffer* b) -> const engine::Buffer& { return b ? *b : *g.means; };
  const gpu::DeformParams p = params(g, time);
  rec.begin_label(name_ + " deform_fwd");
  if (p.n > 0)
    rec.dispatch(sized_pipeline(*ctx_, shaders::Id::deform_fwd, shape_),
                 {planes_, mlp_, *g.means, in(g.log_scales), in(g.quats), in(g.opacity_logits), in(g.sh), in(out.means),
                  in(out.log_scales), in(out.quats), in(out.opacity_logits), in(out.sh)},
                 p, ceil_div(p.n, S4D_DEFORM_WG));
  const engine::Buffer* inputs[S4D_DEFORM_HEADS] = {g.means, g.log_scales, g.quats, g.opacity_logits, g.sh};
  for (uint32_t h = 0; h < S4D_DEFORM_HEADS; ++h)
    if (gpu::deform_head_on(shape_, h) && g.static_count > 0) {  // static: deformed = canonical
      const size_t row = head_floats(h, g.sh_coeffs) * 4;
      rec.copy(*inputs[h], *outputs[h], g.static_count * row, p.n * row, p.n * row);
    }
  rec.end_label();
}

void DeformationField::record_backward(engine::Recorder& rec, const CanonicalGaussians& g, float time,
                                       const DeformedGrads& v) const {
  check_gaussians(g);
  const engine::Buffer* grads[S4D_DEFORM_HEADS] = {v.v_means, v.v_log_scales, v.v_quats, v.v_opacity_logits, v.v_sh};
  require(v.v_means, "v_means", size_t{g.count} * 12, name_);
  for (uint32_t h = 1; h < S4D_DEFORM_HEADS; ++h)
    if (gpu::deform_head_on(shape_, h))
      require(grads[h], (std::string("v_") + kHeadNames[h]).c_str(), size_t{g.count} * head_floats(h, g.sh_coeffs) * 4, name_);
  const engine::DeviceInfo& info = ctx_->info();
  const bool float_atomics = info.float_atomic_add_buffer && info.float_atomic_add_shared && !options_.force_cas_atomics;
  check_llvmpipe(info, shape_, true, !float_atomics, name_);
  const uint32_t moving = g.count - g.static_count;
  if (moving == 0) return;
  auto in = [&](const engine::Buffer* b) -> const engine::Buffer& { return b ? *b : *g.means; };
  const uint32_t rows = scratch_rows();
  gpu::DeformWgradParams wp{};
  wp.shape = shape_;
  wp.row_floats = gpu::deform_scratch_floats(shape_);
  wp.blocks = gpu::deform_wgrad_blocks(shape_);
  const engine::Pipeline& bwd =
      sized_pipeline(*ctx_, float_atomics ? shaders::Id::deform_bwd : shaders::Id::deform_bwd_cas, shape_);
  const engine::Pipeline& wgrad =
      shader_pipeline(*ctx_, float_atomics ? shaders::Id::deform_wgrad : shaders::Id::deform_wgrad_cas);
  rec.begin_label(name_ + (float_atomics ? " deform_bwd" : " deform_bwd_cas"));
  for (uint32_t first = 0; first < moving; first += rows) {
    gpu::DeformParams p = params(g, time);
    p.first = first;
    p.n = std::min(moving - first, rows) + first;
    wp.rows = p.n - first;
    rec.barrier();  // the scratch's previous readers are done
    rec.dispatch(bwd,
                 {planes_, mlp_, *g.means, *v.v_means, in(v.v_log_scales), in(v.v_quats),
                  in(v.v_opacity_logits), in(v.v_sh), v_planes_, scratch_},
                 p, ceil_div(wp.rows, S4D_DEFORM_WG));
    rec.barrier();
    rec.dispatch(wgrad, {scratch_, v_mlp_}, wp,
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
  rec.dispatch(shader_pipeline(*ctx_, shaders::Id::deform_reg), {planes_, v_planes_, reg_partials_}, p,
               ceil_div(p.elements, S4D_DEFORM_REG_WG));
  rec.end_label();
}

}  // namespace s4d::deform
