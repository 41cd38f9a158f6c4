// nn_softmax_rows: each row of a [chunk, n_s] matrix replaced by its softmax (PyTorch
// Softmax(dim=-1)): the row maximum is subtracted before exp, as PyTorch does, so large logits do
// not overflow. One workgroup per row; each invocation strides over the row, so its loops run
// 3 ceil(n_s / S4D_NN_SOFTMAX_WG) times plus the reductions.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "s4d_nn.h"
#include "flat_group.glsl"

layout(local_size_x = S4D_NN_SOFTMAX_WG) in;
layout(push_constant) uniform Push { NnAttnParams p; };
layout(std430, binding = S4D_B_SOFTMAX_DATA) buffer Data { float s[]; };

shared float partial[S4D_NN_SOFTMAX_WG];

// max (is_max) or sum of v over the workgroup; every invocation gets it.
float wg_reduce(float v, bool is_max) {
  uint l = gl_LocalInvocationIndex;
  partial[l] = v;
  barrier();
  for (uint h = S4D_NN_SOFTMAX_WG / 2; h > 0; h >>= 1) {
    if (l < h) partial[l] = is_max ? max(partial[l], partial[l + h]) : partial[l] + partial[l + h];
    barrier();
  }
  float total = partial[0];
  barrier();  // partial[] is reused by the next call
  return total;
}

void main() {
  uint row = flat_group_id(), l = gl_LocalInvocationIndex;
  if (row >= p.chunk) return;  // uniform across the workgroup
  uint base = row * p.n_s;
  float m = -3.402823466e38;
  for (uint j = l; j < p.n_s; j += S4D_NN_SOFTMAX_WG) m = max(m, s[base + j]);
  m = wg_reduce(m, true);
  float sum = 0.0;
  for (uint j = l; j < p.n_s; j += S4D_NN_SOFTMAX_WG) {
    float e = exp(s[base + j] - m);
    s[base + j] = e;
    sum += e;
  }
  float inv = 1.0 / wg_reduce(sum, false);
  for (uint j = l; j < p.n_s; j += S4D_NN_SOFTMAX_WG) s[base + j] *= inv;
}
