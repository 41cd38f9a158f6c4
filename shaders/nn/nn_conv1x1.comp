// nn_conv1x1: 1x1 convolution (PyTorch Conv2d(k=1); a Linear layer on a [in, 1, 1] tensor) with
// bias, optional ReLU, optionally added to what the output holds (MCC's residual, a transformer's).
// Same tiling as nn_conv3x3 (nn_conv_tile.glsl); the variant nn_conv1x1_rows has one-row workgroups.
// S4D_NN_CONV_TRANSPOSE (nn_conv1x1_bwd_input): dx = W^T dy, the input gradient, no bias, bound as
// nn_conv3x3_bwd_input (S4D_B_CONVB_*); p.cin and p.cout are the layer's cout and cin (s4d_nn_grad.h).
#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
#include "s4d_nn_grad.h"
#include "flat_group.glsl"

layout(push_constant) uniform Push { NnConvParams p; };
#if S4D_NN_CONV_TRANSPOSE
layout(std430, binding = S4D_B_CONVB_DY) readonly buffer Dy { float x[]; };
layout(std430, binding = S4D_B_CONVB_WEIGHT) readonly buffer Weight { float weight[]; };
layout(std430, binding = S4D_B_CONVB_DX) buffer Dx { float y[]; };  // read by S4D_NN_FLAG_ACCUMULATE
#else
layout(std430, binding = S4D_B_CONV_IN) readonly buffer In { float x[]; };
layout(std430, binding = S4D_B_CONV_WEIGHT) readonly buffer Weight { float weight[]; };
layout(std430, binding = S4D_B_CONV_BIAS) readonly buffer Bias { float bias[]; };
layout(std430, binding = S4D_B_CONV_OUT) buffer Out { float y[]; };  // read by S4D_NN_FLAG_ACCUMULATE
#endif
#include "nn_conv_tile.glsl"

layout(local_size_x = CONV_WG_X, local_size_y = CONV_WG_Y) in;

void main() {
  ConvTile t = conv_tile();
  if (!t.valid) return;
  uint at[S4D_NN_CONV_PIX];  // strip pixels past the edge read the last one; their outputs are dropped
  [[unroll]] for (uint k = 0; k < S4D_NN_CONV_PIX; ++k) at[k] = t.y * p.width + min(t.x0 + k, p.width - 1);
  float acc[CONV_ACC];
  [[unroll]] for (uint j = 0; j < S4D_NN_CONV_COUT; ++j) {
#if S4D_NN_CONV_TRANSPOSE
    [[unroll]] for (uint k = 0; k < S4D_NN_CONV_PIX; ++k) acc[j * S4D_NN_CONV_PIX + k] = 0.0;
#else
    [[unroll]] for (uint k = 0; k < S4D_NN_CONV_PIX; ++k) acc[j * S4D_NN_CONV_PIX + k] = bias[t.co[j]];
#endif
  }
  uint plane = p.height * p.width;
  for (uint ci = 0; ci < p.cin; ++ci) {
    float v[S4D_NN_CONV_PIX];
    [[unroll]] for (uint k = 0; k < S4D_NN_CONV_PIX; ++k) v[k] = x[ci * plane + at[k]];
    [[unroll]] for (uint j = 0; j < S4D_NN_CONV_COUT; ++j) {
#if S4D_NN_CONV_TRANSPOSE
      float w = weight[ci * p.cout + t.co[j]];
#else
      float w = weight[t.co[j] * p.cin + ci];
#endif
      [[unroll]] for (uint k = 0; k < S4D_NN_CONV_PIX; ++k) acc[j * S4D_NN_CONV_PIX + k] += w * v[k];
    }
  }
  conv_store(t, acc);
}
