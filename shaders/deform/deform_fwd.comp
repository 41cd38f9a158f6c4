// deform_fwd: the deformation field applied to canonical Gaussians at one time (ALGORITHMS.md 3.1).
// One invocation per Gaussian: HexPlane features (6 bilinear samples multiplied per level, levels
// concatenated), the MLP trunk, then each head that is on; the head's output is added to the raw
// canonical parameter and written to the deformed output. It covers Gaussians 0 .. p.n - 1, the
// moving prefix: the host copies the static ones after it unchanged (deformation_field_record.cpp),
// so no invocation idles on a static Gaussian. Outputs of heads that are off are not written.
// MLP weights are read from the storage buffer at uniform addresses (the same for every invocation).
// Specialization constants S4D_DEFORM_SPEC_FEAT / _WIDTH / _TRUNK size the private activation array
// (deform_mlp.glsl); they change capacity only, never results.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "s4d_deform.h"
#include "flat_group.glsl"

layout(local_size_x = S4D_DEFORM_WG) in;
layout(push_constant) uniform Push { DeformParams p; };
layout(std430, binding = S4D_B_DFWD_PLANES) readonly buffer Planes { float planes[]; };
layout(std430, binding = S4D_B_DFWD_MLP) readonly buffer Mlp { float mlp[]; };
layout(std430, binding = S4D_B_DFWD_MEANS) readonly buffer Means { float means[]; };              // [N, 3]
layout(std430, binding = S4D_B_DFWD_LOG_SCALES) readonly buffer LogScales { float log_scales[]; }; // [N, 3]
layout(std430, binding = S4D_B_DFWD_QUATS) readonly buffer Quats { float quats[]; };              // [N, 4]
layout(std430, binding = S4D_B_DFWD_OPACITY_LOGITS) readonly buffer Opacity { float opacity[]; }; // [N]
layout(std430, binding = S4D_B_DFWD_SH) readonly buffer Sh { float sh[]; };                       // [N, K, 3]
layout(std430, binding = S4D_B_DFWD_OUT_MEANS) writeonly buffer OutMeans { float out_means[]; };
layout(std430, binding = S4D_B_DFWD_OUT_LOG_SCALES) writeonly buffer OutLogScales { float out_log_scales[]; };
layout(std430, binding = S4D_B_DFWD_OUT_QUATS) writeonly buffer OutQuats { float out_quats[]; };
layout(std430, binding = S4D_B_DFWD_OUT_OPACITY_LOGITS) writeonly buffer OutOpacity { float out_opacity[]; };
layout(std430, binding = S4D_B_DFWD_OUT_SH) writeonly buffer OutSh { float out_sh[]; };

#include "deform_mlp.glsl"
#include "deform_field.glsl"

// deformed = canonical + delta for head h's `out` values of Gaussian i.
void write_head(uint h, uint i) {
  uint count = deform_head_out(h);
  for (uint k = 0u; k < count; ++k) {
    float d = g_act[ACT_Y2 + k];
    if (h == 0u) out_means[3u * i + k] = means[3u * i + k] + d;
    else if (h == 1u) out_log_scales[3u * i + k] = log_scales[3u * i + k] + d;
    else if (h == 2u) out_quats[4u * i + k] = quats[4u * i + k] + d;
    else if (h == 3u) out_opacity[i] = opacity[i] + d;
    else out_sh[i * 3u * p.sh_coeffs + k] = sh[i * 3u * p.sh_coeffs + k] + d;
  }
}

void main() {
  uint i = flat_group_id() * S4D_DEFORM_WG + gl_LocalInvocationIndex;
  if (i >= p.n) return;
  deform_features(deform_coords(vec3(means[3u * i], means[3u * i + 1u], means[3u * i + 2u])));
  trunk_fwd();
  for (uint h = 0u; h < uint(S4D_DEFORM_HEADS); ++h) {
    if (!deform_head_on(p.shape, h)) continue;
    head_hidden_fwd(h);
    head_out_fwd(h);
    write_head(h, i);
  }
}
