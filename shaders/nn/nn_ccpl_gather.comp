// nn_ccpl_gather: CCPL's difference vectors f[:, anchor] - f[:, neighbour] of the host's sampled
// index pairs; S4D_NN_CCPL_BWD (nn_ccpl_gather_bwd): their adjoint into df (s4d_nn_ccpl.h).
#version 450
#extension GL_GOOGLE_include_directive : require
#include "s4d_nn_ccpl.h"
#include "flat_group.glsl"

layout(local_size_x = S4D_NN_WG) in;
layout(push_constant) uniform Push { NnCcplParams p; };
layout(std430, binding = S4D_B_CCPL_PAIRS) readonly buffer Pairs { uint pairs[]; };
#if S4D_NN_CCPL_BWD
layout(std430, binding = S4D_B_CCPL_F) buffer F { float df[]; };
layout(std430, binding = S4D_B_CCPL_OUT) readonly buffer Out { float dout[]; };
#else
layout(std430, binding = S4D_B_CCPL_F) readonly buffer F { float f[]; };
layout(std430, binding = S4D_B_CCPL_OUT) writeonly buffer Out { float out_[]; };
#endif

void main() {
  uint e = flat_group_id() * S4D_NN_WG + gl_LocalInvocationIndex;
#if S4D_NN_CCPL_BWD
  if (e >= p.channels * p.plane) return;
  uint c = e / p.plane, at = e % p.plane;
  float sum = 0.0;
  for (uint s = 0; s < p.samples; ++s) {
    float d = dout[c * p.samples + s];
    if (pairs[s] == at) sum += d;
    if (pairs[p.samples + s] == at) sum -= d;
  }
  df[e] += sum;
#else
  if (e >= p.channels * p.samples) return;
  uint c = e / p.samples, s = e % p.samples;
  out_[e] = f[c * p.plane + pairs[s]] - f[c * p.plane + pairs[p.samples + s]];
#endif
}
