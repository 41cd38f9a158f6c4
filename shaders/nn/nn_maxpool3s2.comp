// nn_maxpool3s2: 3x3 max pooling, stride 2, floor mode (PyTorch MaxPool2d(3, 2), torchvision
// AlexNet): out = floor((in - 3) / 2) + 1 per side, every window inside the input.
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
  uint base = c * p.in_height * p.in_width + 2 * oy * p.in_width + 2 * ox;
  float m = x[base];
  [[unroll]] for (uint dy = 0; dy < 3; ++dy) {
    [[unroll]] for (uint dx = 0; dx < 3; ++dx) m = max(m, x[base + dy * p.in_width + dx]);
  }
  y[i] = m;
}
