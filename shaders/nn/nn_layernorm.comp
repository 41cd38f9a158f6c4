// nn_layernorm: LayerNorm over the channels of each token of a [C, count] tensor (s4d_nn.h):
// y = (x - mean) / sqrt(var + eps) * weight + bias with the biased variance of the centred values,
// as PyTorch's LayerNorm. One invocation per token; its three loops run over C (the host keeps C
// under S4D_NN_MAX_LOOP).
#version 450
#extension GL_GOOGLE_include_directive : require
#include "s4d_nn.h"
#include "flat_group.glsl"

layout(local_size_x = S4D_NN_WG) in;
layout(push_constant) uniform Push { NnStatsParams p; };
layout(std430, binding = S4D_B_LN_IN) readonly buffer In { float x[]; };
layout(std430, binding = S4D_B_LN_WEIGHT) readonly buffer Weight { float weight[]; };
layout(std430, binding = S4D_B_LN_BIAS) readonly buffer Bias { float bias[]; };
layout(std430, binding = S4D_B_LN_OUT) writeonly buffer Out { float y[]; };

void main() {
  uint t = flat_group_id() * S4D_NN_WG + gl_LocalInvocationIndex;
  if (t >= p.count) return;
  // Sums of x - x[0] rather than of x: a token offset by 1e4 with a unit spread would otherwise lose
  // its mean to the float sum's rounding (measured 2e-3 of the output at 768 channels).
  float shift = x[t], sum = 0.0;
  for (uint c = 0; c < p.channels; ++c) sum += x[c * p.count + t] - shift;
  float mean = sum / float(p.channels), centred = 0.0;  // of x - shift
  for (uint c = 0; c < p.channels; ++c) {
    float d = (x[c * p.count + t] - shift) - mean;
    centred += d * d;
  }
  float inv = inversesqrt(centred / float(p.channels) + p.eps);
  for (uint c = 0; c < p.channels; ++c)
    y[c * p.count + t] = ((x[c * p.count + t] - shift) - mean) * inv * weight[c] + bias[c];
}
