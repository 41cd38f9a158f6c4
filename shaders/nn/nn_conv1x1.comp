// nn_conv1x1: 1x1 convolution (PyTorch Conv2d(k=1); a Linear layer on a [in, 1, 1] tensor) with
// bias, optional ReLU, optionally added to what the output holds (MCC's residual, a transformer's).
// Same tiling as nn_conv3x3 (nn_conv_tile.glsl); the variant nn_conv1x1_rows has one-row workgroups.
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

void main() {
  ConvTile t = conv_tile();
  if (!t.valid) return;
  uint at[S4D_NN_CONV_PIX];  // strip pixels past the edge read the last one; their outputs are dropped
  [[unroll]] for (uint k = 0; k < S4D_NN_CONV_PIX; ++k) at[k] = t.y * p.width + min(t.x0 + k, p.width - 1);
  float acc[CONV_ACC];
  [[unroll]] for (uint j = 0; j < S4D_NN_CONV_COUT; ++j) {
    [[unroll]] for (uint k = 0; k < S4D_NN_CONV_PIX; ++k) acc[j * S4D_NN_CONV_PIX + k] = bias[t.co[j]];
  }
  uint plane = p.height * p.width;
  for (uint ci = 0; ci < p.cin; ++ci) {
    float v[S4D_NN_CONV_PIX];
    [[unroll]] for (uint k = 0; k < S4D_NN_CONV_PIX; ++k) v[k] = x[ci * plane + at[k]];
    [[unroll]] for (uint j = 0; j < S4D_NN_CONV_COUT; ++j) {
      float w = weight[t.co[j] * p.cin + ci];
      [[unroll]] for (uint k = 0; k < S4D_NN_CONV_PIX; ++k) acc[j * S4D_NN_CONV_PIX + k] += w * v[k];
    }
  }
  conv_store(t, acc);
}
