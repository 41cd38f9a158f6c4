// iota: out[i] = first + i for i < n. One thread per element; used to seed argsort values and to
// test 2-D dispatch past 65,535 workgroups.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "s4d_primitives.h"
#include "flat_group.glsl"

layout(local_size_x = S4D_IOTA_WG) in;
layout(push_constant) uniform Push { IotaParams p; };
layout(std430, binding = S4D_B_IOTA_OUT) writeonly buffer Out { uint out_values[]; };  // [n] u32

void main() {
  uint i = flat_group_id() * S4D_IOTA_WG + gl_LocalInvocationIndex;
  if (i < p.n) out_values[i] = p.first + i;
}
