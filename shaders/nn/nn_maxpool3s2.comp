// nn_maxpool3s2: 3x3 max pooling, stride 2, floor mode, padding p.pad (PyTorch MaxPool2d(3, 2, pad):
// 0 in torchvision's AlexNet, 1 in ResNet's stem): out = floor((in + 2 pad - 3) / 2) + 1 per side.
// Padded positions never win (PyTorch pads with -inf); with pad <= 1 every window holds an input.
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
  int y0 = int(2 * oy) - int(p.pad), x0 = int(2 * ox) - int(p.pad);
  uint base = c * p.in_height * p.in_width;
  // The window's centre (y0 + 1, x0 + 1) is always inside the input.
  float m = x[base + uint(y0 + 1) * p.in_width + uint(x0 + 1)];
  [[unroll]] for (int dy = 0; dy < 3; ++dy) {
    [[unroll]] for (int dx = 0; dx < 3; ++dx) {
      int yy = y0 + dy, xx = x0 + dx;
      if (yy >= 0 && yy < int(p.in_height) && xx >= 0 && xx < int(p.in_width))
        m = max(m, x[base + uint(yy) * p.in_width + uint(xx)]);
    }
  }
  y[i] = m;
}
