// nn_upsample_bwd: the adjoint of nn_upsample (nearest, x2): dx[c, y, x] is the sum of dy over the
// 2x2 block [2y, 2y + 1] x [2x, 2x + 1] (s4d_nn_grad.h).
#version 450
#extension GL_GOOGLE_include_directive : require
#include "s4d_nn_grad.h"
#include "flat_group.glsl"

layout(local_size_x = S4D_NN_WG) in;
layout(push_constant) uniform Push { NnResizeParams p; };
layout(std430, binding = S4D_B_RESIZE_IN) readonly buffer In { float dy[]; };
layout(std430, binding = S4D_B_RESIZE_OUT) writeonly buffer Out { float dx[]; };

void main() {
  uint i = flat_group_id() * S4D_NN_WG + gl_LocalInvocationIndex;
  if (i >= p.n_out) return;
  uint ox = i % p.out_width, oy = (i / p.out_width) % p.out_height, c = i / (p.out_width * p.out_height);
  uint top = (c * p.in_height + 2 * oy) * p.in_width + 2 * ox;
  dx[i] = dy[top] + dy[top + 1] + dy[top + p.in_width] + dy[top + p.in_width + 1];
}
