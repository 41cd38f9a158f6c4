// nn_adain: adaptive instance normalisation (Huang & Belongie 2017) per channel c:
// out = alpha (sigma_s (x - mu_c) / sigma_c + mu_s) + (1 - alpha) x, the alpha blend of AdaIN's
// test.py; mode S4D_NN_ADAIN_NORMALISE: out = (x - mu_c) / sigma_c (MCC's normal()).
#version 450
#extension GL_GOOGLE_include_directive : require
#include "s4d_nn.h"
#include "flat_group.glsl"

layout(local_size_x = S4D_NN_WG) in;
layout(push_constant) uniform Push { NnAdainParams p; };
layout(std430, binding = S4D_B_ADAIN_IN) readonly buffer In { float x[]; };
layout(std430, binding = S4D_B_ADAIN_CONTENT_STATS) readonly buffer ContentStats { float content_stats[]; };
layout(std430, binding = S4D_B_ADAIN_STYLE_STATS) readonly buffer StyleStats { float style_stats[]; };
layout(std430, binding = S4D_B_ADAIN_OUT) writeonly buffer Out { float y[]; };

void main() {
  uint i = flat_group_id() * S4D_NN_WG + gl_LocalInvocationIndex;
  if (i >= p.channels * p.count) return;
  uint c = i / p.count;
  float v = x[i], normalised = (v - content_stats[c]) / content_stats[p.channels + c];
  if (p.mode == S4D_NN_ADAIN_NORMALISE) {
    y[i] = normalised;
  } else {
    float styled = normalised * style_stats[p.channels + c] + style_stats[c];
    y[i] = p.alpha * styled + (1.0 - p.alpha) * v;
  }
}
