// nn_patchnce: PatchNCE's cross-entropy of each row of the score matrix q . k with the diagonal as
// the positive, and its gradient w.r.t. the scores (s4d_nn_ccpl.h). One invocation per row, four
// passes over it.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "s4d_nn_ccpl.h"
#include "flat_group.glsl"

layout(local_size_x = S4D_NN_WG) in;
layout(push_constant) uniform Push { NnPatchNceParams p; };
layout(std430, binding = S4D_B_PNCE_SCORES) readonly buffer Scores { float scores[]; };
layout(std430, binding = S4D_B_PNCE_GRAD) writeonly buffer Grad { float grad[]; };
layout(std430, binding = S4D_B_PNCE_LOSS) writeonly buffer Loss { float loss[]; };

void main() {
  uint i = flat_group_id() * S4D_NN_WG + gl_LocalInvocationIndex;
  if (i >= p.samples) return;
  uint row = i * p.samples;
  float top = scores[row] * p.inv_tau;
  for (uint j = 1; j < p.samples; ++j) top = max(top, scores[row + j] * p.inv_tau);
  // 1 - softmax_i as the sum of the others' shares: no cancellation when the positive dominates.
  float others = 0.0;
  for (uint j = 0; j < p.samples; ++j)
    if (j != i) others += exp(scores[row + j] * p.inv_tau - top);
  float positive = exp(scores[row + i] * p.inv_tau - top), sum = positive + others;
  loss[i] = log(sum) + top - scores[row + i] * p.inv_tau;
  float g = p.scale * p.inv_tau / sum;
  for (uint j = 0; j < p.samples; ++j)
    grad[row + j] = j == i ? -g * others : g * exp(scores[row + j] * p.inv_tau - top);
}
