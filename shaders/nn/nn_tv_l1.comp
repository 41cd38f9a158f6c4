// nn_tv_l1: the L1 total variation of a [c, h, w] tensor and its gradient (s4d_nn_grad.h). Each
// element adds the magnitudes of its right and down differences to its workgroup's partial sum, and
// its gradient is the signs of the (up to four) differences it takes part in.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "s4d_nn_grad.h"
#include "flat_group.glsl"

layout(local_size_x = S4D_NN_WG) in;
layout(push_constant) uniform Push { NnTvL1Params p; };
layout(std430, binding = S4D_B_TV1_X) readonly buffer X { float x[]; };
layout(std430, binding = S4D_B_TV1_GRAD) buffer Grad { float grad[]; };
layout(std430, binding = S4D_B_TV1_PARTIALS) writeonly buffer Partials { float partials[]; };

#include "nn_wg_sum.glsl"

void main() {
  uint g = flat_group_id(), i = g * S4D_NN_WG + gl_LocalInvocationIndex, n = p.channels * p.height * p.width;
  if (g * S4D_NN_WG >= n) return;  // uniform across the workgroup
  float magnitude = 0.0;
  if (i < n) {
    uint col = i % p.width, row = (i / p.width) % p.height;
    float v = x[i], d = 0.0;
    if (col + 1 < p.width) {
      magnitude += abs(v - x[i + 1]);
      d += sign(v - x[i + 1]);
    }
    if (row + 1 < p.height) {
      magnitude += abs(v - x[i + p.width]);
      d += sign(v - x[i + p.width]);
    }
    if (col > 0) d -= sign(x[i - 1] - v);
    if (row > 0) d -= sign(x[i - p.width] - v);
    grad[i] += p.weight * d;
  }
  float total = wg_sum(magnitude);
  if (gl_LocalInvocationIndex == 0) partials[g] = total;
}
