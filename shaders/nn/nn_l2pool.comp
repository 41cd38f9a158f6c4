// nn_l2pool: DISTS's L2 pooling (Ding et al. 2020, DISTS_pt.py L2pooling), one invocation per output
// value: sqrt(sum over the 3x3 window of g * x^2 + S4D_NN_L2POOL_EPS), g = [1 2 1]^T [1 2 1] / 16
// (hanning(5)[1:-1] normalised), stride 2, zero padding 1, each channel on its own; the output is
// ceil(in / 2) per side.
#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
#include "s4d_nn.h"
#include "flat_group.glsl"

layout(local_size_x = S4D_NN_WG) in;
layout(push_constant) uniform Push { NnResizeParams p; };
layout(std430, binding = S4D_B_RESIZE_IN) readonly buffer In { float x[]; };
layout(std430, binding = S4D_B_RESIZE_OUT) writeonly buffer Out { float y[]; };

void main() {
  uint i = flat_group_id() * S4D_NN_WG + gl_LocalInvocationIndex;
  if (i >= p.n_out) return;
  uint ox = i % p.out_width, oy = (i / p.out_width) % p.out_height, c = i / (p.out_width * p.out_height);
  uint base = c * p.in_height * p.in_width;
  float sum = 0.0;
  [[unroll]] for (int dy = -1; dy <= 1; ++dy) {
    int sy = 2 * int(oy) + dy;
    if (sy < 0 || sy >= int(p.in_height)) continue;
    [[unroll]] for (int dx = -1; dx <= 1; ++dx) {
      int sx = 2 * int(ox) + dx;
      if (sx < 0 || sx >= int(p.in_width)) continue;
      float v = x[base + uint(sy) * p.in_width + uint(sx)];
      sum += float((2 - abs(dy)) * (2 - abs(dx))) * v * v;
    }
  }
  y[i] = sqrt(sum / 16.0 + S4D_NN_L2POOL_EPS);
}
