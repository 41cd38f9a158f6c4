// nn_avgpool3: 3x3 mean pooling, stride 1, no padding (PyTorch AvgPool2d(3, 1)), [c, h - 2, w - 2];
// S4D_NN_AVGPOOL_BWD (nn_avgpool3_bwd): its adjoint, each input value the ninth of the gradients of
// the (up to 9) windows that cover it (s4d_nn_grad.h).
#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
#include "s4d_nn_grad.h"
#include "flat_group.glsl"

layout(local_size_x = S4D_NN_WG) in;
layout(push_constant) uniform Push { NnResizeParams p; };
layout(std430, binding = S4D_B_RESIZE_IN) readonly buffer In { float x[]; };
layout(std430, binding = S4D_B_RESIZE_OUT) writeonly buffer Out { float y[]; };

void main() {
  uint i = flat_group_id() * S4D_NN_WG + gl_LocalInvocationIndex;
  if (i >= p.n_out) return;
  float sum = 0.0;
#if S4D_NN_AVGPOOL_BWD
  // x is dy [c, out_h, out_w]; i runs over the pool's input [c, in_h, in_w].
  int px = int(i % p.in_width), py = int((i / p.in_width) % p.in_height), c = int(i / (p.in_width * p.in_height));
  [[unroll]] for (int dy = -2; dy <= 0; ++dy) {
    [[unroll]] for (int dx = -2; dx <= 0; ++dx) {
      int oy = py + dy, ox = px + dx;
      if (oy >= 0 && ox >= 0 && oy < int(p.out_height) && ox < int(p.out_width))
        sum += x[(c * int(p.out_height) + oy) * int(p.out_width) + ox];
    }
  }
#else
  uint ox = i % p.out_width, oy = (i / p.out_width) % p.out_height, c = i / (p.out_width * p.out_height);
  [[unroll]] for (uint dy = 0; dy < 3; ++dy) {
    [[unroll]] for (uint dx = 0; dx < 3; ++dx) sum += x[(c * p.in_height + oy + dy) * p.in_width + ox + dx];
  }
#endif
  y[i] = sum / 9.0;
}
