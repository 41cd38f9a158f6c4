// grad_add: dst += src, element-wise; sums the gradients of the views of a batch into one.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "s4d_optim.h"
#include "flat_group.glsl"

layout(local_size_x = S4D_ADD_WG) in;
layout(push_constant) uniform Push { AddParams p; };
layout(std430, binding = S4D_B_ADD_DST) buffer Dst { float dst[]; };
layout(std430, binding = S4D_B_ADD_SRC) readonly buffer Src { float src[]; };

void main() {
  uint i = flat_group_id() * S4D_ADD_WG + gl_LocalInvocationIndex;
  if (i < p.n) dst[i] += src[i];
}
