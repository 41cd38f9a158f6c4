// nn_channel_dots: per channel sums[c] = sum_p a[c, p] and sums[C + c] = sum_p a[c, p] b[c, p], one
// workgroup per channel (s4d_nn_grad.h): the reductions of the normalisation's and MCC's backward.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "s4d_nn_grad.h"
#include "flat_group.glsl"

layout(local_size_x = S4D_NN_STATS_WG) in;
layout(push_constant) uniform Push { NnStatsBwdParams p; };
layout(std430, binding = S4D_B_DOTS_A) readonly buffer A { float a[]; };
layout(std430, binding = S4D_B_DOTS_B) readonly buffer B { float b[]; };
layout(std430, binding = S4D_B_DOTS_SUMS) writeonly buffer Sums { float sums[]; };

#include "nn_wg_sum.glsl"

void main() {
  uint c = flat_group_id(), l = gl_LocalInvocationIndex;
  if (c >= p.channels) return;  // uniform across the workgroup
  uint base = c * p.count;
  float sum = 0.0, dot = 0.0;
  for (uint i = l; i < p.count; i += S4D_NN_STATS_WG) {
    sum += a[base + i];
    dot += a[base + i] * b[base + i];
  }
  sum = wg_sum(sum);
  dot = wg_sum(dot);
  if (l == 0) {
    sums[c] = sum;
    sums[p.channels + c] = dot;
  }
}
