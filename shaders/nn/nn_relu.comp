// nn_relu: x = max(x, 0) in place (for layers whose ReLU is not fused into the convolution).
#version 450
#extension GL_GOOGLE_include_directive : require
#include "s4d_nn.h"
#include "flat_group.glsl"

layout(local_size_x = S4D_NN_WG) in;
layout(push_constant) uniform Push { NnEltParams p; };
layout(std430, binding = S4D_B_RELU_DATA) buffer Data { float data[]; };

void main() {
  uint i = flat_group_id() * S4D_NN_WG + gl_LocalInvocationIndex;
  if (i < p.n) data[i] = max(data[i], 0.0);
}
