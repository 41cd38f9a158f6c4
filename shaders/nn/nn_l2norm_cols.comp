// nn_l2norm_cols: each column of a [c, samples] matrix divided by its norm + eps (CCPL's Normalize);
// S4D_NN_L2NORM_BWD (nn_l2norm_cols_bwd): its gradient (s4d_nn_ccpl.h). One invocation per column.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "s4d_nn_ccpl.h"
#include "flat_group.glsl"

layout(local_size_x = S4D_NN_WG) in;
layout(push_constant) uniform Push { NnCcplParams p; };
layout(std430, binding = S4D_B_L2N_X) readonly buffer X { float x[]; };
#if S4D_NN_L2NORM_BWD
layout(std430, binding = S4D_B_L2N_Y) readonly buffer Y { float dy[]; };
layout(std430, binding = S4D_B_L2N_DX) writeonly buffer DX { float dx[]; };
#else
layout(std430, binding = S4D_B_L2N_Y) writeonly buffer Y { float y[]; };
#endif

void main() {
  uint s = flat_group_id() * S4D_NN_WG + gl_LocalInvocationIndex;
  if (s >= p.samples) return;
  float squares = 0.0;
  for (uint c = 0; c < p.channels; ++c) squares += x[c * p.samples + s] * x[c * p.samples + s];
  float n = sqrt(squares), d = n + float(S4D_NN_L2NORM_EPS);
#if S4D_NN_L2NORM_BWD
  float dot_ = 0.0;
  for (uint c = 0; c < p.channels; ++c) dot_ += x[c * p.samples + s] * dy[c * p.samples + s];
  float k = n > 0.0 ? dot_ / (n * d * d) : 0.0;
  for (uint c = 0; c < p.channels; ++c) dx[c * p.samples + s] = dy[c * p.samples + s] / d - x[c * p.samples + s] * k;
#else
  for (uint c = 0; c < p.channels; ++c) y[c * p.samples + s] = x[c * p.samples + s] / d;
#endif
}
