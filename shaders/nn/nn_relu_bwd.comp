// nn_relu_bwd: dy = y > 0 ? dy : 0 in place, y the ReLU's output (s4d_nn_grad.h).
#version 450
#extension GL_GOOGLE_include_directive : require
#include "s4d_nn_grad.h"
#include "flat_group.glsl"

layout(local_size_x = S4D_NN_WG) in;
layout(push_constant) uniform Push { NnEltParams p; };
layout(std430, binding = S4D_B_RELUB_DY) buffer Dy { float dy[]; };
layout(std430, binding = S4D_B_RELUB_Y) readonly buffer Y { float y[]; };

void main() {
  uint i = flat_group_id() * S4D_NN_WG + gl_LocalInvocationIndex;
  if (i < p.n && !(y[i] > 0.0)) dy[i] = 0.0;
}
