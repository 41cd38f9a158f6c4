// nn_selfsim_bwd: the gradient of HGST's self-similarity term (s4d_nn_grad.h). With S = sum v^2 over
// the tensor, T = sum_c mu_c M_c (channel means and maxima) and the term sum_c (1 - mu_c M_c / S):
// d/dv[c, p] = -(M_c / (L S) + [p = argmax_c] mu_c / S) + 2 T v[c, p] / S^2, scaled by weight / C.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "s4d_nn_grad.h"
#include "flat_group.glsl"

layout(local_size_x = S4D_NN_WG) in;
layout(push_constant) uniform Push { NnSelfsimParams p; };
layout(std430, binding = S4D_B_SELFSIM_V) readonly buffer V { float v[]; };
layout(std430, binding = S4D_B_SELFSIM_SUMS) readonly buffer Sums { float sums[]; };
layout(std430, binding = S4D_B_SELFSIM_MAX) readonly buffer Max { float maxima[]; };
layout(std430, binding = S4D_B_SELFSIM_GRAD) buffer Grad { float grad[]; };
layout(std430, binding = S4D_B_SELFSIM_VALUE) writeonly buffer Value { float value[]; };

void main() {
  uint i = flat_group_id() * S4D_NN_WG + gl_LocalInvocationIndex;
  if (i >= p.channels * p.count) return;
  float s = 0.0, t = 0.0, l = float(p.count);
  for (uint c = 0; c < p.channels; ++c) {
    s += sums[p.channels + c];
    t += sums[c] / l * maxima[c];
  }
  uint c = i / p.count, at = i % p.count;
  float mu = sums[c] / l, m = maxima[c];
  float d = -m / (l * s) + 2.0 * t * v[i] / (s * s);
  if (float(at) == maxima[p.channels + c]) d -= mu / s;
  grad[i] += p.weight / float(p.channels) * d;
  if (i == 0) value[0] = float(p.channels) - t / s;
}
