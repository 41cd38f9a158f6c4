// nn_im2col: PyTorch's F.unfold(x, k, padding=pad, stride) of one image: out[(c k + ky) k + kx, oy, ox]
// = x[c, oy stride - pad + ky, ox stride - pad + kx], 0 in the padding, so Conv2d(k, stride, pad) is
// a 1x1 convolution (nn_conv1x1's tiles) of the result with the weights [cout, cin k k] as stored.
// One invocation per output value; NnConvStridedParams with cout = cin k k (no weights, bias or flags).
#version 450
#extension GL_GOOGLE_include_directive : require
#include "s4d_nn.h"
#include "flat_group.glsl"

layout(local_size_x = S4D_NN_WG) in;
layout(push_constant) uniform Push { NnConvStridedParams p; };
layout(std430, binding = S4D_B_IM2COL_IN) readonly buffer In { float x[]; };     // [cin, in_h, in_w]
layout(std430, binding = S4D_B_IM2COL_OUT) writeonly buffer Out { float y[]; };  // [cin k k, out_h, out_w]

void main() {
  uint i = flat_group_id() * S4D_NN_WG + gl_LocalInvocationIndex;
  if (i >= p.n_out) return;
  uint ox = i % p.out_width, oy = (i / p.out_width) % p.out_height, row = i / (p.out_width * p.out_height);
  uint kx = row % p.kernel, ky = (row / p.kernel) % p.kernel, c = row / (p.kernel * p.kernel);
  int sy = int(oy * p.stride + ky) - int(p.pad), sx = int(ox * p.stride + kx) - int(p.pad);
  bool inside = sy >= 0 && sy < int(p.in_height) && sx >= 0 && sx < int(p.in_width);
  y[i] = inside ? x[(c * p.in_height + uint(sy)) * p.in_width + uint(sx)] : 0.0;
}
