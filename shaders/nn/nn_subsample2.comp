// nn_subsample2: every second row and column, x[c, 2 oy, 2 ox] (out = ceil(in / 2) per side): with
// nn_conv1x1 after it, ResNet's 1x1 stride-2 downsampling convolution at nn_conv1x1's tiled speed.
#version 450
#extension GL_GOOGLE_include_directive : require
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
  y[i] = x[(c * p.in_height + 2 * oy) * p.in_width + 2 * ox];
}
