// densify_reset_opacity: graphdeco's opacity reset. One thread per Gaussian: logit <- min(logit,
// value) where value = logit(max_opacity), which equals min(sigmoid(logit), max_opacity) written as a
// logit without the round trip; both Adam moments of the logits are zeroed.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "s4d_densify.h"
#include "flat_group.glsl"

layout(local_size_x = S4D_DENSIFY_WG) in;
layout(push_constant) uniform Push { SlotParams p; };  // n = Gaussians, value = the largest logit
layout(std430, binding = S4D_B_RESET_OPACITY) buffer Opacity { float opacity_logits[]; };  // [N]
layout(std430, binding = S4D_B_RESET_M) writeonly buffer M { float m[]; };                  // [N]
layout(std430, binding = S4D_B_RESET_V) writeonly buffer V { float v[]; };                  // [N]

void main() {
  uint i = flat_group_id() * S4D_DENSIFY_WG + gl_LocalInvocationIndex;
  if (i >= p.n) return;
  opacity_logits[i] = min(opacity_logits[i], p.value);
  m[i] = 0.0;
  v[i] = 0.0;
}
