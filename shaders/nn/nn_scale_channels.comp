// nn_scale_channels: x[c, i] *= s[c] in place (MCC: the content features times the style weights).
#version 450
#extension GL_GOOGLE_include_directive : require
#include "s4d_nn.h"
#include "flat_group.glsl"

layout(local_size_x = S4D_NN_WG) in;
layout(push_constant) uniform Push { NnEltParams p; };
layout(std430, binding = S4D_B_SCALE_DATA) buffer Data { float data[]; };
layout(std430, binding = S4D_B_SCALE_FACTORS) readonly buffer Factors { float factors[]; };

void main() {
  uint i = flat_group_id() * S4D_NN_WG + gl_LocalInvocationIndex;
  if (i < p.n) data[i] *= factors[i / p.count];
}
