// nn_group_norm: GroupNorm(groups, C, eps) (+ ReLU) of each cell of a batch of small images stacked
// along H (s4d_nn.h, NnGroupNormParams), statistics over the cell's window only, zeros elsewhere in
// the cell. One workgroup per (cell, group): the mean, then the biased variance of the centred
// values (two passes, as PyTorch's GroupNorm), summed in shared memory, so no subgroup size is
// assumed; then every value of the group's channels in the cell is written.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "s4d_nn.h"
#include "flat_group.glsl"

layout(local_size_x = S4D_NN_STATS_WG) in;
layout(push_constant) uniform Push { NnGroupNormParams p; };
layout(std430, binding = S4D_B_GN_IN) readonly buffer In { float x[]; };
layout(std430, binding = S4D_B_GN_WEIGHT) readonly buffer Weight { float weight[]; };
layout(std430, binding = S4D_B_GN_BIAS) readonly buffer Bias { float bias[]; };
layout(std430, binding = S4D_B_GN_OUT) writeonly buffer Out { float y[]; };

shared float partial[S4D_NN_STATS_WG];

float wg_sum(float v) {
  uint l = gl_LocalInvocationIndex;
  partial[l] = v;
  barrier();
  for (uint s = S4D_NN_STATS_WG / 2; s > 0; s >>= 1) {
    if (l < s) partial[l] += partial[l + s];
    barrier();
  }
  float total = partial[0];
  barrier();  // partial[] is reused by the next call
  return total;
}

// The flat index in x of the window's value i (channel-major over the group's channels).
uint window_index(uint i, uint first_channel, uint first_row) {
  uint per_channel = p.rows * p.cols;
  uint ch = first_channel + i / per_channel, r = i % per_channel;
  return (ch * p.height + first_row + p.row0 + r / p.cols) * p.width + p.col0 + r % p.cols;
}

void main() {
  uint id = flat_group_id(), l = gl_LocalInvocationIndex;
  uint cells = p.height / p.cell_h;
  if (id >= cells * p.groups) return;  // uniform across the workgroup
  uint cell = id / p.groups, group = id % p.groups;
  uint group_channels = p.channels / p.groups, first_channel = group * group_channels, first_row = cell * p.cell_h;
  uint n = group_channels * p.rows * p.cols;
  float sum = 0.0;
  for (uint i = l; i < n; i += S4D_NN_STATS_WG) sum += x[window_index(i, first_channel, first_row)];
  float mean = wg_sum(sum) / float(n);
  float centred = 0.0;
  for (uint i = l; i < n; i += S4D_NN_STATS_WG) {
    float d = x[window_index(i, first_channel, first_row)] - mean;
    centred += d * d;
  }
  float inv = inversesqrt(wg_sum(centred) / float(n) + p.eps);
  uint per_channel = p.cell_h * p.width;
  for (uint i = l; i < group_channels * per_channel; i += S4D_NN_STATS_WG) {
    uint ch = first_channel + i / per_channel, r = i % per_channel, row = r / p.width, col = r % p.width;
    uint at = (ch * p.height + first_row + row) * p.width + col;
    float v = 0.0;
    if (row >= p.row0 && row < p.row0 + p.rows && col >= p.col0 && col < p.col0 + p.cols) {
      v = (x[at] - mean) * inv * weight[ch] + bias[ch];
      if ((p.flags & S4D_NN_FLAG_RELU) != 0u) v = max(v, 0.0);
    }
    y[at] = v;
  }
}
