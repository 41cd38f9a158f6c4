// nn_mse: a squared-error loss term between two tensors: grad += scale (a - b) and each workgroup's
// sum of (a - b)^2 in partials, which the host adds up (s4d_nn_grad.h).
#version 450
#extension GL_GOOGLE_include_directive : require
#include "s4d_nn_grad.h"
#include "flat_group.glsl"

layout(local_size_x = S4D_NN_WG) in;
layout(push_constant) uniform Push { NnMseParams p; };
layout(std430, binding = S4D_B_MSE_A) readonly buffer A { float a[]; };
layout(std430, binding = S4D_B_MSE_B) readonly buffer B { float b[]; };
layout(std430, binding = S4D_B_MSE_GRAD) buffer Grad { float grad[]; };
layout(std430, binding = S4D_B_MSE_PARTIALS) writeonly buffer Partials { float partials[]; };

#include "nn_wg_sum.glsl"

void main() {
  uint g = flat_group_id(), i = g * S4D_NN_WG + gl_LocalInvocationIndex;
  if (g * S4D_NN_WG >= p.n) return;  // uniform across the workgroup
  float d = 0.0;
  if (i < p.n) {
    d = a[i] - b[i];
    grad[i] += p.scale * d;
  }
  float total = wg_sum(d * d);
  if (gl_LocalInvocationIndex == 0) partials[g] = total;
}
