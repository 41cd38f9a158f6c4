// nn_gelu: x = x Phi(x) in place, the exact (erf) GELU of PyTorch (s4d_nn.h). With z = |x| / sqrt(2),
// erfc(z) = poly(t) exp(-z^2), t = 1 / (1 + 0.3275911 z) (Abramowitz & Stegun 7.1.26), and
// Phi(x) = 1 - erfc(z) / 2 for x >= 0, erfc(z) / 2 for x < 0.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "s4d_nn.h"
#include "flat_group.glsl"

layout(local_size_x = S4D_NN_WG) in;
layout(push_constant) uniform Push { NnEltParams p; };
layout(std430, binding = S4D_B_GELU_DATA) buffer Data { float data[]; };

void main() {
  uint i = flat_group_id() * S4D_NN_WG + gl_LocalInvocationIndex;
  if (i >= p.n) return;
  float x = data[i], z = abs(x) * 0.70710678118654752;
  float t = 1.0 / (1.0 + 0.3275911 * z);
  float poly = t * (0.254829592 + t * (-0.284496736 + t * (1.421413741 + t * (-1.453152027 + t * 1.061405429))));
  float half_erfc = 0.5 * poly * exp(-z * z);
  data[i] = x * (x >= 0.0 ? 1.0 - half_erfc : half_erfc);
}
