// nn_squares_over_sum_bwd: dL/dx of MCC's a = S2 / S1 (S1 = sum_p x, S2 = sum_p x^2 per channel):
// dx = da (2 x - a) / S1, with (S1, S2) from nn_channel_dots of (x, x) (s4d_nn_grad.h).
#version 450
#extension GL_GOOGLE_include_directive : require
#include "s4d_nn_grad.h"
#include "flat_group.glsl"

layout(local_size_x = S4D_NN_WG) in;
layout(push_constant) uniform Push { NnStatsBwdParams p; };
layout(std430, binding = S4D_B_SOSB_X) readonly buffer X { float x[]; };
layout(std430, binding = S4D_B_SOSB_SUMS) readonly buffer Sums { float sums[]; };
layout(std430, binding = S4D_B_SOSB_DA) readonly buffer Da { float da[]; };
layout(std430, binding = S4D_B_SOSB_DX) writeonly buffer Dx { float dx[]; };

void main() {
  uint i = flat_group_id() * S4D_NN_WG + gl_LocalInvocationIndex;
  if (i >= p.channels * p.count) return;
  uint c = i / p.count;
  float s1 = sums[c], a = sums[p.channels + c] / s1;
  dx[i] = da[c] * (2.0 * x[i] - a) / s1;
}
