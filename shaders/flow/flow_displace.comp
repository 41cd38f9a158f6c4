// flow_displace: one thread per Gaussian. From the screen lanes of two frames (flow_project's
// output, [N*3] each) writes the colour (du, dv, 0) = to - from into colors [N*3], or 0 when the
// mean is behind the near plane in either frame (its motion has no screen meaning there).
#version 450
#extension GL_GOOGLE_include_directive : require
#include "s4d_flow.h"
#include "flat_group.glsl"

layout(local_size_x = S4D_FLOW_WG) in;
layout(push_constant) uniform Push { FlowDisplaceParams p; };
layout(std430, binding = S4D_B_FLOWD_FROM) readonly buffer From { float from_screen[]; };  // [N, 3]
layout(std430, binding = S4D_B_FLOWD_TO) readonly buffer To { float to_screen[]; };        // [N, 3]
layout(std430, binding = S4D_B_FLOWD_COLORS) writeonly buffer Colors { float colors[]; };  // [N, 3]

void main() {
  uint i = flat_group_id() * S4D_FLOW_WG + gl_LocalInvocationIndex;
  if (i >= p.n) return;
  uint o = S4D_FLOW_SCREEN_STRIDE * i;
  bool valid = from_screen[o + S4D_FLOW_SCREEN_VALID] > 0.5 && to_screen[o + S4D_FLOW_SCREEN_VALID] > 0.5;
  colors[3 * i] = valid ? to_screen[o + S4D_FLOW_SCREEN_U] - from_screen[o + S4D_FLOW_SCREEN_U] : 0.0;
  colors[3 * i + 1] = valid ? to_screen[o + S4D_FLOW_SCREEN_V] - from_screen[o + S4D_FLOW_SCREEN_V] : 0.0;
  colors[3 * i + 2] = 0.0;
}
