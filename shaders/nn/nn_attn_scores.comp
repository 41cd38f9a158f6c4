// nn_attn_scores: AdaAttN's attention logits for one chunk of content positions (s4d_nn.h):
// S[i, j] = sum_k Q[k, first + i] K[k, j], one invocation per score; the loop over the key
// channels is the only one (the host keeps it under S4D_NN_MAX_LOOP).
#version 450
#extension GL_GOOGLE_include_directive : require
#include "s4d_nn.h"
#include "flat_group.glsl"

layout(local_size_x = S4D_NN_WG) in;
layout(push_constant) uniform Push { NnAttnParams p; };
layout(std430, binding = S4D_B_ATTN_Q) readonly buffer Q { float q[]; };
layout(std430, binding = S4D_B_ATTN_K) readonly buffer K { float k[]; };
layout(std430, binding = S4D_B_ATTN_SCORES) writeonly buffer Scores { float scores[]; };

void main() {
  uint e = flat_group_id() * S4D_NN_WG + gl_LocalInvocationIndex;
  if (e >= p.chunk * p.n_s) return;
  uint i = p.first + e / p.n_s, j = e % p.n_s;
  float acc = 0.0;
  for (uint c = 0; c < p.channels; ++c) acc += q[c * p.n_c + i] * k[c * p.n_s + j];
  scores[e] = acc;
}
