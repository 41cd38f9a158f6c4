// nn_mean_std_bwd: dL/dx of the per-channel mean and std = sqrt(unbiased variance + eps), or of the
// normalisation (x - mu) / std built on them (mode S4D_NN_STATSB_*, s4d_nn_grad.h); added to dx.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "s4d_nn_grad.h"
#include "flat_group.glsl"

layout(local_size_x = S4D_NN_WG) in;
layout(push_constant) uniform Push { NnStatsBwdParams p; };
layout(std430, binding = S4D_B_STATSB_X) readonly buffer X { float x[]; };
layout(std430, binding = S4D_B_STATSB_STATS) readonly buffer Stats { float stats[]; };
layout(std430, binding = S4D_B_STATSB_DSTATS) readonly buffer Dstats { float dstats[]; };
layout(std430, binding = S4D_B_STATSB_DY) readonly buffer Dy { float dy[]; };
layout(std430, binding = S4D_B_STATSB_DX) buffer Dx { float dx[]; };

void main() {
  uint i = flat_group_id() * S4D_NN_WG + gl_LocalInvocationIndex;
  if (i >= p.channels * p.count) return;
  uint c = i / p.count;
  float mu = stats[c], sigma = stats[p.channels + c], dmu = dstats[c], dsigma = dstats[p.channels + c];
  float direct = 0.0;
  if (p.mode == S4D_NN_STATSB_NORMALISE) {
    direct = dy[i] / sigma;
    dmu = -dmu / sigma;
    dsigma = -dsigma / sigma;
  }
  dx[i] += direct + dmu / float(p.count) + dsigma * (x[i] - mu) / (float(p.count - 1) * sigma);
}
