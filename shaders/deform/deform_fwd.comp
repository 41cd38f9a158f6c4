// deform_fwd: the forward of one layer set of the deformation MLP (ALGORITHMS.md 3.1; sets and the
// scratch row layout in s4d_deform.h) over the Gaussians p.first .. p.n - 1 of the moving prefix.
// An invocation is S4D_DEFORM_ROWS Gaussians (scratch rows) x S4D_DEFORM_BLOCK outputs of one Linear layer:
// out[o] = bias[o] + sum_i weight[o][i] x[i] with x the layer's input columns (stored after their
// ReLU), summed from the bias in input order. The trunk's and the heads' hidden layers store
// ReLU(out) in their activation columns; a head's output layer adds out to the canonical raw
// parameter and writes the deformed one (only heads that are on). Every invocation of a workgroup
// reads the same weights, so their addresses are uniform; the loop runs in_dim iterations.
// S4D_SH_HALF=1 (deform_fwd_half) reads the canonical SH as packed halves (half_storage.glsl), the
// render side's half storage; the deformed SH it writes stay float.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "s4d_deform.h"
#include "flat_group.glsl"
#include "half_storage.glsl"
#ifndef S4D_SH_HALF
#define S4D_SH_HALF 0
#endif

layout(local_size_x = S4D_DEFORM_WG) in;
layout(push_constant) uniform Push { DeformParams p; };
layout(std430, binding = S4D_B_DFWD_MLP) readonly buffer Mlp { float mlp[]; };
layout(std430, binding = S4D_B_DFWD_SCRATCH) buffer Scratch { float scratch[]; };                 // [rows, row floats]
layout(std430, binding = S4D_B_DFWD_MEANS) readonly buffer Means { float means[]; };              // [N, 3]
layout(std430, binding = S4D_B_DFWD_LOG_SCALES) readonly buffer LogScales { float log_scales[]; }; // [N, 3]
layout(std430, binding = S4D_B_DFWD_QUATS) readonly buffer Quats { float quats[]; };              // [N, 4]
layout(std430, binding = S4D_B_DFWD_OPACITY_LOGITS) readonly buffer Opacity { float opacity[]; }; // [N]
#if S4D_SH_HALF
layout(std430, binding = S4D_B_DFWD_SH) readonly buffer Sh { uint sh_words[]; };  // [ceil(N*K*3 / 2)] f16 pairs
float sh_at(uint j) { return half_element(sh_words[j >> 1], j); }
#else
layout(std430, binding = S4D_B_DFWD_SH) readonly buffer Sh { float sh[]; };  // [N, K, 3]
float sh_at(uint j) { return sh[j]; }
#endif
layout(std430, binding = S4D_B_DFWD_OUT_MEANS) writeonly buffer OutMeans { float out_means[]; };
layout(std430, binding = S4D_B_DFWD_OUT_LOG_SCALES) writeonly buffer OutLogScales { float out_log_scales[]; };
layout(std430, binding = S4D_B_DFWD_OUT_QUATS) writeonly buffer OutQuats { float out_quats[]; };
layout(std430, binding = S4D_B_DFWD_OUT_OPACITY_LOGITS) writeonly buffer OutOpacity { float out_opacity[]; };
layout(std430, binding = S4D_B_DFWD_OUT_SH) writeonly buffer OutSh { float out_sh[]; };

#include "deform_mlp.glsl"

// deformed = canonical + d for output k of head h of Gaussian i.
void write_head(uint h, uint i, uint k, float d) {
  if (h == 0u) out_means[3u * i + k] = means[3u * i + k] + d;
  else if (h == 1u) out_log_scales[3u * i + k] = log_scales[3u * i + k] + d;
  else if (h == 2u) out_quats[4u * i + k] = quats[4u * i + k] + d;
  else if (h == 3u) out_opacity[i] = opacity[i] + d;
  else out_sh[i * 3u * p.sh_coeffs + k] = sh_at(i * 3u * p.sh_coeffs + k) + d;
}

void main() {
  uvec4 rows;
  bvec4 live;
  uint layer, block;
  if (!deform_block(false, false, rows, live, layer, block)) return;
  uint in_dim = deform_layer_in(p.shape, layer), out_dim = deform_layer_out(p.shape, layer);
  uint o0 = block * uint(S4D_DEFORM_BLOCK), w = deform_layer_offset(p.shape, layer);
  uvec4 o = deform_quad(o0, out_dim);
  uvec4 bias = w + out_dim * in_dim + o, weight = w + o * in_dim;
  uint row_floats = deform_scratch_floats(p.shape);
  uvec4 base = rows * row_floats, x_at = base + deform_in_col(p.shape, layer);
  mat4 acc;  // acc[r][k]: row r, output o0 + k
  acc[0] = vec4(mlp[bias.x], mlp[bias.y], mlp[bias.z], mlp[bias.w]);
  acc[1] = acc[0];
  acc[2] = acc[0];
  acc[3] = acc[0];
  for (uint i = 0u; i < in_dim; ++i) {
    vec4 wi = vec4(mlp[weight.x + i], mlp[weight.y + i], mlp[weight.z + i], mlp[weight.w + i]);
    acc[0] += wi * scratch[x_at.x + i];
    acc[1] += wi * scratch[x_at.y + i];
    acc[2] += wi * scratch[x_at.z + i];
    acc[3] += wi * scratch[x_at.w + i];
  }
  bool head_out = deform_layer_is_head_out(p.shape, layer);
  uint h = head_out ? deform_layer_head(p.shape, layer) : 0u;
  uint col = head_out ? 0u : deform_act_col(p.shape, deform_out_slot(p.shape, layer)) + o0;
  for (uint r = 0u; r < uint(S4D_DEFORM_ROWS); ++r) {
    if (!live[r]) break;  // rows past the pass come last
    for (uint k = 0u; k < uint(S4D_DEFORM_BLOCK) && o0 + k < out_dim; ++k) {
      if (head_out) write_head(h, p.first + rows[r], o0 + k, acc[r][k]);
      else scratch[base[r] + col + k] = max(acc[r][k], 0.0);
    }
  }
}
