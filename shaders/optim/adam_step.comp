// adam_step: one Adam update of a parameter tensor (PyTorch semantics):
// (g clamped to +-S4D_ADAM_MAX_GRAD), m = b1 m + (1 - b1) g, v = b2 v + (1 - b2) g^2, p -= lr (m / (1 - b1^t)) / (sqrt(v / (1 - b2^t)) + eps).
#version 450
#extension GL_GOOGLE_include_directive : require
#include "s4d_optim.h"
#include "flat_group.glsl"

layout(local_size_x = S4D_ADAM_WG) in;
layout(push_constant) uniform Push { AdamParams p; };
layout(std430, binding = S4D_B_ADAM_GROUPS) readonly buffer Groups { AdamGroup groups[]; };
layout(std430, binding = S4D_B_ADAM_PARAMS) buffer Params { float params[]; };
layout(std430, binding = S4D_B_ADAM_GRADS) readonly buffer Grads { float grads[]; };
layout(std430, binding = S4D_B_ADAM_M) buffer M { float m[]; };
layout(std430, binding = S4D_B_ADAM_V) buffer V { float v[]; };

void main() {
  uint i = flat_group_id() * S4D_ADAM_WG + gl_LocalInvocationIndex;
  if (i >= p.n) return;
  AdamGroup h = groups[i % p.row < p.head ? p.group : p.tail_group];
  float g = grads[i];
  if (abs(g) > S4D_ADAM_MAX_GRAD) g = sign(g) * S4D_ADAM_MAX_GRAD;
  float mi = h.beta1 * m[i] + (1.0 - h.beta1) * g;
  float vi = h.beta2 * v[i] + (1.0 - h.beta2) * g * g;
  m[i] = mi;
  v[i] = vi;
  params[i] -= h.lr * (mi * h.inv_bias1) / (sqrt(vi) * h.inv_sqrt_bias2 + h.eps);
}
