// nn_conv3x3: 3x3 convolution with padding 1, bias, optional ReLU (nn_conv_tile.glsl: an invocation
// computes a strip of pixels for a block of output channels). S4D_NN_CONV_PAD_ZERO = 0: reflection
// padding (PyTorch ReflectionPad2d(1) + Conv2d(k=3), the AdaIN-style networks; variant nn_conv3x3);
// 1: zero padding (Conv2d(k=3, padding=1), torchvision's VGG; variant nn_conv3x3_zero). The padded
// rows and columns are found once; per input channel and kernel row the strip loads PIX + 2 inputs
// and 3 weights per output channel. The loop over input channels is the only runtime loop
// (llvmpipe's 65,535-iteration cap; the rest is unrolled).
#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
#include "s4d_nn.h"
#include "flat_group.glsl"

layout(push_constant) uniform Push { NnConvParams p; };
layout(std430, binding = S4D_B_CONV_IN) readonly buffer In { float x[]; };
layout(std430, binding = S4D_B_CONV_WEIGHT) readonly buffer Weight { float weight[]; };
layout(std430, binding = S4D_B_CONV_BIAS) readonly buffer Bias { float bias[]; };
layout(std430, binding = S4D_B_CONV_OUT) buffer Out { float y[]; };  // read by S4D_NN_FLAG_ACCUMULATE
#include "nn_conv_tile.glsl"

layout(local_size_x = CONV_WG_X, local_size_y = CONV_WG_Y) in;

// Reflection padding 1: index -1 reads 1, index n reads n - 2 (the host requires n >= 2). Columns
// past n + 1 (strip pixels outside the image) are clamped; their outputs are dropped.
uint reflect1(int i, uint n) { return uint(i < 0 ? -i : (i >= int(n) ? max(2 * int(n) - 2 - i, 0) : i)); }

// Zero padding: an index outside [0, n) reads index 0 (always loadable) and is masked to 0 below.
bool inside(int i, uint n) { return i >= 0 && i < int(n); }
uint pad_index(int i, uint n) {
#if S4D_NN_CONV_PAD_ZERO
  return inside(i, n) ? uint(i) : 0u;
#else
  return reflect1(i, n);
#endif
}
bool pad_keeps(int i, uint n) {
#if S4D_NN_CONV_PAD_ZERO
  return inside(i, n);
#else
  return true;
#endif
}

void main() {
  ConvTile t = conv_tile();
  if (!t.valid) return;
  uint rows[3], cols[S4D_NN_CONV_PIX + 2];
  bool row_in[3], col_in[S4D_NN_CONV_PIX + 2];
  [[unroll]] for (int d = 0; d < 3; ++d) {
    rows[d] = pad_index(int(t.y) + d - 1, p.height) * p.width;
    row_in[d] = pad_keeps(int(t.y) + d - 1, p.height);
  }
  [[unroll]] for (int d = 0; d < S4D_NN_CONV_PIX + 2; ++d) {
    cols[d] = pad_index(int(t.x0) + d - 1, p.width);
    col_in[d] = pad_keeps(int(t.x0) + d - 1, p.width);
  }
  float acc[CONV_ACC];
  [[unroll]] for (uint j = 0; j < S4D_NN_CONV_COUT; ++j) {
    [[unroll]] for (uint k = 0; k < S4D_NN_CONV_PIX; ++k) acc[j * S4D_NN_CONV_PIX + k] = bias[t.co[j]];
  }
  uint plane = p.height * p.width;
  for (uint ci = 0; ci < p.cin; ++ci) {
    [[unroll]] for (uint dy = 0; dy < 3; ++dy) {
      float v[S4D_NN_CONV_PIX + 2];
      [[unroll]] for (uint d = 0; d < S4D_NN_CONV_PIX + 2; ++d)
        v[d] = row_in[dy] && col_in[d] ? x[ci * plane + rows[dy] + cols[d]] : 0.0;
      [[unroll]] for (uint j = 0; j < S4D_NN_CONV_COUT; ++j) {
        uint w = (t.co[j] * p.cin + ci) * 9 + dy * 3;
        float w0 = weight[w], w1 = weight[w + 1], w2 = weight[w + 2];
        [[unroll]] for (uint k = 0; k < S4D_NN_CONV_PIX; ++k)
          acc[j * S4D_NN_CONV_PIX + k] += w0 * v[k] + w1 * v[k + 1] + w2 * v[k + 2];
      }
    }
  }
  conv_store(t, acc);
}
