// nn_conv_strided: Conv2d(cin, cout, k, stride, padding) with zero padding, bias and optional ReLU
// (torchvision AlexNet's 11x11 stride-4 and 5x5 layers), one invocation per output value
// (co, oy, ox) looping over the input channels and the k x k taps inside the image. A plain loop:
// these layers are few and small next to VGG's, so no register tiling as in nn_conv3x3.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "s4d_nn.h"
#include "flat_group.glsl"

layout(local_size_x = S4D_NN_WG) in;
layout(push_constant) uniform Push { NnConvStridedParams p; };
layout(std430, binding = S4D_B_CONV_IN) readonly buffer In { float x[]; };            // [cin, in_h, in_w]
layout(std430, binding = S4D_B_CONV_WEIGHT) readonly buffer Weight { float weight[]; };  // [cout, cin, k, k]
layout(std430, binding = S4D_B_CONV_BIAS) readonly buffer Bias { float bias[]; };        // [cout]
layout(std430, binding = S4D_B_CONV_OUT) writeonly buffer Out { float y[]; };            // [cout, out_h, out_w]

void main() {
  uint i = flat_group_id() * S4D_NN_WG + gl_LocalInvocationIndex;
  if (i >= p.n_out) return;
  uint ox = i % p.out_width, oy = (i / p.out_width) % p.out_height, co = i / (p.out_width * p.out_height);
  int y0 = int(oy * p.stride) - int(p.pad), x0 = int(ox * p.stride) - int(p.pad);
  // The taps inside the image: the zero padding contributes nothing.
  uint ky0 = uint(max(-y0, 0)), ky1 = uint(min(int(p.kernel), int(p.in_height) - y0));
  uint kx0 = uint(max(-x0, 0)), kx1 = uint(min(int(p.kernel), int(p.in_width) - x0));
  float acc = bias[co];
  for (uint ci = 0; ci < p.cin; ++ci) {
    uint wbase = (co * p.cin + ci) * p.kernel * p.kernel, xbase = ci * p.in_height * p.in_width;
    for (uint ky = ky0; ky < ky1; ++ky) {
      uint row = xbase + uint(y0 + int(ky)) * p.in_width;
      for (uint kx = kx0; kx < kx1; ++kx) acc += weight[wbase + ky * p.kernel + kx] * x[row + uint(x0 + int(kx))];
    }
  }
  y[i] = (p.flags & S4D_NN_FLAG_RELU) != 0u ? max(acc, 0.0) : acc;
}
