// nn_attn_apply: AdaAttN's attention-weighted statistics for one chunk of content positions
// (s4d_nn.h): M = sum_j P[i, j] V[c, j], S = sqrt(relu(sum_j P[i, j] V[c, j]^2 - M^2)) and
// out[c, first + i] = S * content[c, first + i] + M. One invocation per output; the loop over the
// style positions is the only one (the host keeps it under S4D_NN_MAX_LOOP).
// With S4D_NN_ATTN_AVERAGE (variant nn_attn_average): out[c, first + i] = M, a transformer's
// attention, with no content binding (the output at S4D_B_ATTN_AVG_OUT).
#version 450
#extension GL_GOOGLE_include_directive : require
#include "s4d_nn.h"
#include "flat_group.glsl"

layout(local_size_x = S4D_NN_WG) in;
layout(push_constant) uniform Push { NnAttnParams p; };
layout(std430, binding = S4D_B_ATTN_P) readonly buffer P { float w[]; };
layout(std430, binding = S4D_B_ATTN_V) readonly buffer V { float v[]; };
#if S4D_NN_ATTN_AVERAGE
layout(std430, binding = S4D_B_ATTN_AVG_OUT) writeonly buffer Out { float y[]; };
#else
layout(std430, binding = S4D_B_ATTN_CONTENT) readonly buffer Content { float content[]; };
layout(std430, binding = S4D_B_ATTN_OUT) writeonly buffer Out { float y[]; };
#endif

void main() {
  uint e = flat_group_id() * S4D_NN_WG + gl_LocalInvocationIndex;
  if (e >= p.channels * p.chunk) return;
  uint c = e / p.chunk, i = e % p.chunk;
  uint at = c * p.n_c + p.first + i;
#if S4D_NN_ATTN_AVERAGE
  float mean = 0.0;
  for (uint j = 0; j < p.n_s; ++j) mean += w[i * p.n_s + j] * v[c * p.n_s + j];
  y[at] = mean;
#else
  float mean = 0.0, squares = 0.0;
  for (uint j = 0; j < p.n_s; ++j) {
    float pw = w[i * p.n_s + j], val = v[c * p.n_s + j];
    mean += pw * val;
    squares += pw * val * val;
  }
  float stddev = sqrt(max(squares - mean * mean, 0.0));
  y[at] = stddev * content[at] + mean;
#endif
}
