// nn_channel_stats: per-channel statistics, one workgroup per channel. Default: mean, then
// std = sqrt(unbiased variance + eps) from the centred squares in a second pass (AdaIN's
// calc_mean_std). S4D_NN_STATS_MCC: a = sum(x^2) / sum(x) (MCC's style weights, ALGORITHMS.md 4.2).
// The workgroup sums in shared memory, so no subgroup size is assumed.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "s4d_nn.h"
#include "flat_group.glsl"

layout(local_size_x = S4D_NN_STATS_WG) in;
layout(push_constant) uniform Push { NnStatsParams p; };
layout(std430, binding = S4D_B_STATS_IN) readonly buffer In { float x[]; };
layout(std430, binding = S4D_B_STATS_OUT) writeonly buffer Out { float stats[]; };

#include "nn_wg_sum.glsl"

void main() {
  uint c = flat_group_id(), l = gl_LocalInvocationIndex;
  if (c >= p.channels) return;  // uniform across the workgroup
  uint base = c * p.count;
#if S4D_NN_STATS_MCC
  float sum = 0.0, squares = 0.0;
  for (uint i = l; i < p.count; i += S4D_NN_STATS_WG) {
    float v = x[base + i];
    sum += v;
    squares += v * v;
  }
  float a = wg_sum(squares) / wg_sum(sum);
  if (l == 0) stats[c] = a;
#else
  float sum = 0.0;
  for (uint i = l; i < p.count; i += S4D_NN_STATS_WG) sum += x[base + i];
  float mean = wg_sum(sum) / float(p.count);
  float centred = 0.0;
  for (uint i = l; i < p.count; i += S4D_NN_STATS_WG) {
    float d = x[base + i] - mean;
    centred += d * d;
  }
  float var = wg_sum(centred) / float(p.count - 1);
  if (l == 0) {
    stats[c] = mean;
    stats[p.channels + c] = sqrt(var + p.eps);
  }
#endif
}
