// nn_maxpool: 2x2 max pooling, stride 2, ceil mode (PyTorch MaxPool2d(2, 2, 0, ceil_mode=True)):
// out size ceil(in / 2); a window hanging over the last row or column takes the values it covers.
// nn_avgpool2 (S4D_NN_POOL_AVERAGE=1): AvgPool2d(2) (CLIP's ModifiedResNet), the mean of the four
// values; the host gives it the floor-mode size floor(in / 2), so no window hangs over the edge.
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
  uint x0 = 2 * ox, y0 = 2 * oy, x1 = min(x0 + 1, p.in_width - 1), y1 = min(y0 + 1, p.in_height - 1);
  uint base = c * p.in_height * p.in_width;
  // Clamping repeats a covered value instead of reading past the edge; the max is the same.
#if S4D_NN_POOL_AVERAGE
  // PyTorch's order: the window's sum, row by row, then divided by the count.
  y[i] = (x[base + y0 * p.in_width + x0] + x[base + y0 * p.in_width + x1] + x[base + y1 * p.in_width + x0] +
          x[base + y1 * p.in_width + x1]) / 4.0;
#else
  y[i] = max(max(x[base + y0 * p.in_width + x0], x[base + y0 * p.in_width + x1]),
             max(x[base + y1 * p.in_width + x0], x[base + y1 * p.in_width + x1]));
#endif
}
