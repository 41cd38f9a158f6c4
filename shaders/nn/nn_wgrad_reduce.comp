// nn_wgrad_reduce: sums nn_conv_wgrad's per-chunk partials into the weight and bias gradients
// (s4d_nn_grad.h), one invocation per slot looping over the chunks.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "s4d_nn_grad.h"
#include "flat_group.glsl"

layout(local_size_x = S4D_NN_WG) in;
layout(push_constant) uniform Push { NnWgradReduceParams p; };
layout(std430, binding = S4D_B_WGRED_PARTIAL) readonly buffer Partial { float partial[]; };
layout(std430, binding = S4D_B_WGRED_DW) buffer Dw { float dw[]; };  // read by S4D_NN_FLAG_ACCUMULATE
layout(std430, binding = S4D_B_WGRED_DB) buffer Db { float db[]; };

void main() {
  uint i = flat_group_id() * S4D_NN_WG + gl_LocalInvocationIndex;
  if (i >= p.slots) return;
  float sum = 0.0;
  for (uint c = 0; c < p.chunks; ++c) sum += partial[c * p.slots + i];
  bool add = (p.flags & S4D_NN_FLAG_ACCUMULATE) != 0u;
  if (i < p.weights) {
    dw[i] = add ? dw[i] + sum : sum;
  } else {
    db[i - p.weights] = add ? db[i - p.weights] + sum : sum;
  }
}
