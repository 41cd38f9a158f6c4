// nn_vit_embed: a vision transformer's input tokens (s4d_nn.h): the class token (folded into pos's
// first column by the host) followed by the patch embeddings, plus the position embedding.
// nn_prepend_token (S4D_NN_VIT_FIRST_ONLY=1): no position embedding, pos holds only the first token
// [c] (CLIP's attention pooling: the spatial mean before the feature map's positions).
#version 450
#extension GL_GOOGLE_include_directive : require
#include "s4d_nn.h"
#include "flat_group.glsl"

layout(local_size_x = S4D_NN_WG) in;
layout(push_constant) uniform Push { NnEltParams p; };  // n = c * tokens, count = tokens
layout(std430, binding = S4D_B_VIT_PATCHES) readonly buffer Patches { float patches[]; };
layout(std430, binding = S4D_B_VIT_POS) readonly buffer Pos { float pos[]; };
layout(std430, binding = S4D_B_VIT_OUT) writeonly buffer Out { float y[]; };

void main() {
  uint i = flat_group_id() * S4D_NN_WG + gl_LocalInvocationIndex;
  if (i >= p.n) return;
  uint c = i / p.count, t = i % p.count;
#if S4D_NN_VIT_FIRST_ONLY
  y[i] = t == 0u ? pos[c] : patches[c * (p.count - 1u) + t - 1u];
#else
  y[i] = pos[i] + (t == 0u ? 0.0 : patches[c * (p.count - 1u) + t - 1u]);
#endif
}
