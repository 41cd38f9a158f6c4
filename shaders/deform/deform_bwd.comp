// deform_bwd: the input cotangents of one layer set of the deformation MLP (sets and the scratch
// row layout in s4d_deform.h) over the Gaussians p.first .. p.n - 1 of the moving prefix, after
// deform_fwd has stored the activations. An invocation is S4D_DEFORM_ROWS Gaussians x
// S4D_DEFORM_BLOCK inputs:
// v_in[i] = ReLU'(x_i) sum_o weight[o][i] v_out[o] (no ReLU factor for the trunk's first layer,
// whose input is the features), summed in output order. With p.shared_input (the heads' hidden
// layers, all fed by the trunk output) it sums that over the set's layers in head order, as the
// twin does. Every v_out is read from the row (deform_cot put the heads' there). The loop runs
// out_dim iterations per layer: at most S4D_DEFORM_HEADS x W.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "s4d_deform.h"
#include "flat_group.glsl"

layout(local_size_x = S4D_DEFORM_WG) in;
layout(push_constant) uniform Push { DeformParams p; };
layout(std430, binding = S4D_B_DBWD_MLP) readonly buffer Mlp { float mlp[]; };
layout(std430, binding = S4D_B_DBWD_SCRATCH) buffer Scratch { float scratch[]; };  // [rows, row floats]

#include "deform_mlp.glsl"

void main() {
  uvec4 rows;
  bvec4 live;
  uint layer, block;
  bool shared_input = p.shared_input != 0u;
  if (!deform_block(true, shared_input, rows, live, layer, block)) return;
  uint in_dim = deform_layer_in(p.shape, layer), i0 = block * uint(S4D_DEFORM_BLOCK);
  uvec4 ii = deform_quad(i0, in_dim);
  uint row_floats = deform_scratch_floats(p.shape);
  uvec4 base = rows * row_floats;
  uint in_col = deform_in_col(p.shape, layer);
  mat4 v_in = mat4(0.0);  // v_in[r][k]: row r, input i0 + k
  for (uint k = 0u; k < (shared_input ? p.layers : 1u); ++k) {
    uint l = layer + 2u * k, out_dim = deform_layer_out(p.shape, l);
    uvec4 weight = deform_layer_offset(p.shape, l) + ii, v_at = base + deform_v_out_col(p.shape, l);
    mat4 acc = mat4(0.0);
    for (uint o = 0u; o < out_dim; ++o, weight += in_dim) {
      vec4 wo = vec4(mlp[weight.x], mlp[weight.y], mlp[weight.z], mlp[weight.w]);
      vec4 v = vec4(scratch[v_at.x + o], scratch[v_at.y + o], scratch[v_at.z + o], scratch[v_at.w + o]);
      acc[0] += wo * v.x;
      acc[1] += wo * v.y;
      acc[2] += wo * v.z;
      acc[3] += wo * v.w;
    }
    for (uint r = 0u; r < uint(S4D_DEFORM_ROWS); ++r) {
      if (layer > 0u) {  // ReLU': the stored input is ReLU(pre-activation)
        uint x_at = base[r] + in_col;
        vec4 x = vec4(scratch[x_at + ii.x], scratch[x_at + ii.y], scratch[x_at + ii.z], scratch[x_at + ii.w]);
        acc[r] = mix(acc[r], vec4(0.0), lessThanEqual(x, vec4(0.0)));
      }
      v_in[r] += acc[r];
    }
  }
  uint col = deform_v_in_col(p.shape, layer) + i0;
  for (uint r = 0u; r < uint(S4D_DEFORM_ROWS); ++r) {
    if (!live[r]) break;  // rows past the pass come last
    for (uint k = 0u; k < uint(S4D_DEFORM_BLOCK) && i0 + k < in_dim; ++k) scratch[base[r] + col + k] = v_in[r][k];
  }
}
