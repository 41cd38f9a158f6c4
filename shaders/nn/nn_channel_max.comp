// nn_channel_max: per channel the maximum and the index of its first occurrence (s4d_nn_grad.h), one
// workgroup per channel: each invocation scans a stride of the values, then a shared-memory
// reduction keeps the larger value, the smaller index on ties.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "s4d_nn_grad.h"
#include "flat_group.glsl"

layout(local_size_x = S4D_NN_STATS_WG) in;
layout(push_constant) uniform Push { NnStatsBwdParams p; };
layout(std430, binding = S4D_B_CMAX_IN) readonly buffer In { float x[]; };
layout(std430, binding = S4D_B_CMAX_OUT) writeonly buffer Out { float result[]; };

shared float best[S4D_NN_STATS_WG];
shared uint at[S4D_NN_STATS_WG];

void main() {
  uint c = flat_group_id(), l = gl_LocalInvocationIndex;
  if (c >= p.channels) return;  // uniform across the workgroup
  float m = -3.0e38;
  uint arg = 0xffffffffu;
  for (uint i = l; i < p.count; i += S4D_NN_STATS_WG) {
    float v = x[c * p.count + i];
    if (v > m) {
      m = v;
      arg = i;
    }
  }
  best[l] = m;
  at[l] = arg;
  barrier();
  for (uint s = S4D_NN_STATS_WG / 2; s > 0; s >>= 1) {
    if (l < s && (best[l + s] > best[l] || (best[l + s] == best[l] && at[l + s] < at[l]))) {
      best[l] = best[l + s];
      at[l] = at[l + s];
    }
    barrier();
  }
  if (l == 0) {
    result[c] = best[0];
    result[p.channels + c] = float(at[0]);
  }
}
