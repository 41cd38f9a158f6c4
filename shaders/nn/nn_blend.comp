// nn_blend: out = alpha a + beta b (MCCNet's content / style blend of its channel weights; AdaAttN's
// sum of its relu4_1 and upsampled relu5_1 attention outputs).
#version 450
#extension GL_GOOGLE_include_directive : require
#include "s4d_nn.h"
#include "flat_group.glsl"

layout(local_size_x = S4D_NN_WG) in;
layout(push_constant) uniform Push { NnBlendParams p; };
layout(std430, binding = S4D_B_BLEND_A) readonly buffer A { float a[]; };
layout(std430, binding = S4D_B_BLEND_B) readonly buffer B { float b[]; };
layout(std430, binding = S4D_B_BLEND_OUT) writeonly buffer Out { float y[]; };

void main() {
  uint i = flat_group_id() * S4D_NN_WG + gl_LocalInvocationIndex;
  if (i < p.n) y[i] = p.alpha * a[i] + p.beta * b[i];
}
