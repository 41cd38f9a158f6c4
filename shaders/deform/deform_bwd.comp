// deform_bwd: the input cotangents of one layer set of the deformation MLP (sets and the scratch
// row layout in s4d_deform.h) over the Gaussians p.first .. p.n - 1 of the moving prefix, after
// deform_fwd has stored the activations. An invocation is one Gaussian x S4D_DEFORM_BLOCK inputs:
// v_in[i] = ReLU'(x_i) sum_o weight[o][i] v_out[o] (no ReLU factor for the trunk's first layer,
// whose input is the features), summed in output order. With p.shared_input (the heads' hidden
// layers, all fed by the trunk output) it sums that over the set's layers in head order, as the
// twin does. A head's output layer reads v_out from the deformed parameters' cotangents, and the
// first block of each such layer copies them to the row for deform_wgrad. The loop runs out_dim
// iterations per layer: at most S4D_DEFORM_HEADS x W.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "s4d_deform.h"
#include "flat_group.glsl"

layout(local_size_x = S4D_DEFORM_WG) in;
layout(push_constant) uniform Push { DeformParams p; };
layout(std430, binding = S4D_B_DBWD_MLP) readonly buffer Mlp { float mlp[]; };
layout(std430, binding = S4D_B_DBWD_SCRATCH) buffer Scratch { float scratch[]; };  // [rows, row floats]
layout(std430, binding = S4D_B_DBWD_V_MEANS) readonly buffer VMeans { float v_means[]; };          // [N, 3]
layout(std430, binding = S4D_B_DBWD_V_LOG_SCALES) readonly buffer VLogScales { float v_log_scales[]; };
layout(std430, binding = S4D_B_DBWD_V_QUATS) readonly buffer VQuats { float v_quats[]; };
layout(std430, binding = S4D_B_DBWD_V_OPACITY_LOGITS) readonly buffer VOpacity { float v_opacity[]; };
layout(std430, binding = S4D_B_DBWD_V_SH) readonly buffer VSh { float v_sh[]; };

#include "deform_mlp.glsl"

// dL/d output k of head h for Gaussian i.
float head_cotangent(uint h, uint i, uint k) {
  if (h == 0u) return v_means[3u * i + k];
  if (h == 1u) return v_log_scales[3u * i + k];
  if (h == 2u) return v_quats[4u * i + k];
  if (h == 3u) return v_opacity[i];
  return v_sh[i * 3u * p.sh_coeffs + k];
}

void main() {
  uint row, layer, block;
  bool live;
  bool shared_input = p.shared_input != 0u;
  if (!deform_block(true, shared_input, row, live, layer, block)) return;
  uint in_dim = deform_layer_in(p.shape, layer), i0 = block * uint(S4D_DEFORM_BLOCK), gaussian = p.first + row;
  uvec4 ii = deform_quad(i0, in_dim);
  uint base = row * deform_scratch_floats(p.shape), x_at = base + deform_in_col(p.shape, layer);
  vec4 x = vec4(scratch[x_at + ii.x], scratch[x_at + ii.y], scratch[x_at + ii.z], scratch[x_at + ii.w]);
  vec4 v_in = vec4(0.0);
  for (uint k = 0u; k < (shared_input ? p.layers : 1u); ++k) {
    uint l = layer + 2u * k, out_dim = deform_layer_out(p.shape, l), w = deform_layer_offset(p.shape, l);
    bool head_out = deform_layer_is_head_out(p.shape, l);
    uint h = head_out ? deform_layer_head(p.shape, l) : 0u, v_at = base + deform_v_out_col(p.shape, l);
    uvec4 weight = w + ii;
    vec4 acc = vec4(0.0);
    for (uint o = 0u; o < out_dim; ++o, weight += in_dim) {
      float v = head_out ? head_cotangent(h, gaussian, o) : scratch[v_at + o];
      acc.x += mlp[weight.x] * v;
      acc.y += mlp[weight.y] * v;
      acc.z += mlp[weight.z] * v;
      acc.w += mlp[weight.w] * v;
    }
    if (layer > 0u) acc = mix(acc, vec4(0.0), lessThanEqual(x, vec4(0.0)));  // ReLU': the stored input is ReLU(pre)
    v_in += acc;
    if (head_out && block == 0u && live)
      for (uint o = 0u; o < out_dim; ++o) scratch[v_at + o] = head_cotangent(h, gaussian, o);
  }
  if (!live) return;
  uint at = base + deform_v_in_col(p.shape, layer);
  for (uint k = 0u; k < uint(S4D_DEFORM_BLOCK) && i0 + k < in_dim; ++k) scratch[at + i0 + k] = v_in[k];
}
