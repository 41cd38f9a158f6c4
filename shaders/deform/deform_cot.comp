// deform_cot: the cotangents of the deformed parameters of the Gaussians p.first .. p.n - 1 of the
// moving prefix, for each head that is on, to the head-output columns of their scratch rows (layout
// in s4d_deform.h), one invocation per Gaussian. deform_bwd and deform_wgrad then read every
// cotangent from the rows: a head-dependent buffer choice inside their loops would cost, on
// llvmpipe, a masked load from every buffer per iteration.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "s4d_deform.h"
#include "flat_group.glsl"

layout(local_size_x = S4D_DEFORM_WG) in;
layout(push_constant) uniform Push { DeformParams p; };
layout(std430, binding = S4D_B_DCOT_V_MEANS) readonly buffer VMeans { float v_means[]; };          // [N, 3]
layout(std430, binding = S4D_B_DCOT_V_LOG_SCALES) readonly buffer VLogScales { float v_log_scales[]; }; // [N, 3]
layout(std430, binding = S4D_B_DCOT_V_QUATS) readonly buffer VQuats { float v_quats[]; };          // [N, 4]
layout(std430, binding = S4D_B_DCOT_V_OPACITY_LOGITS) readonly buffer VOpacity { float v_opacity[]; }; // [N]
layout(std430, binding = S4D_B_DCOT_V_SH) readonly buffer VSh { float v_sh[]; };                   // [N, K, 3]
layout(std430, binding = S4D_B_DCOT_SCRATCH) writeonly buffer Scratch { float scratch[]; };       // [rows, row floats]

void main() {
  uint row = flat_group_id() * S4D_DEFORM_WG + gl_LocalInvocationIndex, i = p.first + row;
  if (i >= p.n) return;
  uint at = row * deform_scratch_floats(p.shape) + deform_cot_col(p.shape, deform_slots(p.shape));
  if (deform_head_on(p.shape, 0u)) {
    for (uint k = 0u; k < 3u; ++k) scratch[at + k] = v_means[3u * i + k];
    at += 3u;
  }
  if (deform_head_on(p.shape, 1u)) {
    for (uint k = 0u; k < 3u; ++k) scratch[at + k] = v_log_scales[3u * i + k];
    at += 3u;
  }
  if (deform_head_on(p.shape, 2u)) {
    for (uint k = 0u; k < 4u; ++k) scratch[at + k] = v_quats[4u * i + k];
    at += 4u;
  }
  if (deform_head_on(p.shape, 3u)) {
    scratch[at] = v_opacity[i];
    at += 1u;
  }
  if (deform_head_on(p.shape, 4u))
    for (uint k = 0u; k < 3u * uint(S4D_DEFORM_SH_COEFFS); ++k) scratch[at + k] = v_sh[i * 3u * p.sh_coeffs + k];
}
