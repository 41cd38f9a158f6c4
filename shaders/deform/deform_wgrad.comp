// deform_wgrad: the MLP weight and bias gradients from the scratch rows (per Gaussian, each Linear
// layer's input after its ReLU, from deform_fwd, and its output cotangent, from deform_bwd; layout
// in s4d_deform.h). For layer l,
// dL/d weight[o][i] = sum over rows of v[o] x[i] and dL/d bias[o] = sum of v[o].
// One invocation per (4x4 weight block, S4D_DEFORM_WGRAD_ROWS rows): it sums the block's 16 weights
// (and, for blocks at input 0, their 4 biases) over its rows in registers, in row order, then adds
// each non-zero sum to v_mlp with one atomic. Blocks at the layer's edges read the last input or
// output again in their spare lanes and do not add those sums.
// S4D_FLOAT_ATOMICS=1 adds with float atomics; 0 with compare-and-swap loops.
#version 450
#extension GL_GOOGLE_include_directive : require
#if S4D_FLOAT_ATOMICS
#extension GL_EXT_shader_atomic_float : require
#endif
#include "s4d_deform.h"
#include "flat_group.glsl"

layout(local_size_x = S4D_DEFORM_WGRAD_WG) in;
layout(push_constant) uniform Push { DeformWgradParams p; };
layout(std430, binding = S4D_B_DWG_SCRATCH) readonly buffer Scratch { float scratch[]; };  // [rows, row_floats]
#if S4D_FLOAT_ATOMICS
layout(std430, binding = S4D_B_DWG_V_MLP) buffer VMlp { float v_mlp[]; };
void add_v_mlp(uint k, float value) { atomicAdd(v_mlp[k], value); }
#else
layout(std430, binding = S4D_B_DWG_V_MLP) buffer VMlp { uint v_mlp[]; };
// Compare-and-swap add; the first read is atomic, as a plain load would race the swaps.
void add_v_mlp(uint k, float value) {
  uint old = atomicOr(v_mlp[k], 0u);
  for (;;) {
    uint seen = atomicCompSwap(v_mlp[k], old, floatBitsToUint(uintBitsToFloat(old) + value));
    if (seen == old) break;
    old = seen;
  }
}
#endif

void main() {
  uint t = flat_group_id() * S4D_DEFORM_WGRAD_WG + gl_LocalInvocationIndex;
  uint b = t % p.blocks, first = t / p.blocks * uint(S4D_DEFORM_WGRAD_ROWS);
  if (first >= p.rows) return;
  uint l = 0u;
  for (; b >= deform_layer_blocks(p.shape, l); ++l) b -= deform_layer_blocks(p.shape, l);
  uint in_dim = deform_layer_in(p.shape, l), out_dim = deform_layer_out(p.shape, l);
  uint i_blocks = (in_dim + 3u) / 4u, o0 = b / i_blocks * 4u, i0 = b % i_blocks * 4u;
  uvec4 xi = min(uvec4(i0) + uvec4(0u, 1u, 2u, 3u), uvec4(in_dim - 1u)) + deform_in_col(p.shape, l);
  uvec4 vo = min(uvec4(o0) + uvec4(0u, 1u, 2u, 3u), uvec4(out_dim - 1u)) + deform_v_out_col(p.shape, l);
  mat4 acc = mat4(0.0);  // acc[c][r]: input i0 + c, output o0 + r
  vec4 bias = vec4(0.0);
  uint end = min(first + uint(S4D_DEFORM_WGRAD_ROWS), p.rows);
  for (uint at = first * p.row_floats, stop = end * p.row_floats; at < stop; at += p.row_floats) {
    vec4 x = vec4(scratch[at + xi.x], scratch[at + xi.y], scratch[at + xi.z], scratch[at + xi.w]);
    vec4 v = vec4(scratch[at + vo.x], scratch[at + vo.y], scratch[at + vo.z], scratch[at + vo.w]);
    acc[0] += v * x.x;
    acc[1] += v * x.y;
    acc[2] += v * x.z;
    acc[3] += v * x.w;
    bias += v;
  }
  uint offset = deform_layer_offset(p.shape, l);
  for (uint r = 0u; r < 4u; ++r) {
    uint o = o0 + r;
    if (o >= out_dim) break;
    for (uint c = 0u; c < 4u; ++c)
      if (i0 + c < in_dim && acc[c][r] != 0.0) add_v_mlp(offset + o * in_dim + i0 + c, acc[c][r]);
    if (i0 == 0u && bias[r] != 0.0) add_v_mlp(offset + out_dim * in_dim + o, bias[r]);
  }
}
