// Shared layouts of the CCPL kernels (Wu et al. 2022, "CCPL: Contrastive Coherence Preserving Loss",
// and HGST's variant, ALGORITHMS.md 4.5; host side training/kernels/nn/ccpl.cpp, twins in
// training/ref/include/s4d/ref/ccpl_ref.h). Features are one image [C, H*W]; the S sampled
// difference vectors and everything after them are [C, S], one column per sample. The sample
// indices come from the host (its seeded generator), so the kernels draw nothing.
#ifndef S4D_NN_CCPL_H
#define S4D_NN_CCPL_H
#include "s4d_nn.h"

// nn_ccpl_gather: out[c, s] = f[c, anchor[s]] - f[c, neighbour[s]], one invocation per output.
// nn_ccpl_gather_bwd (the same file, S4D_NN_CCPL_BWD): its adjoint, df[c, p] += sum_s dout[c, s]
// ([anchor[s] == p] - [neighbour[s] == p]), one invocation per element of df looping over the
// samples (no atomics: an index may repeat).
#define S4D_B_CCPL_F 0      // [c, plane] features (bwd: df, added to)
#define S4D_B_CCPL_PAIRS 1  // [2, samples] uint: the anchors' flat indices, then the neighbours'
#define S4D_B_CCPL_OUT 2    // [c, samples] differences (bwd: their gradient, read)

// nn_l2norm_cols: y[:, s] = x[:, s] / (|x[:, s]| + S4D_NN_L2NORM_EPS) (CCPL's Normalize), one
// invocation per column looping over the channels. nn_l2norm_cols_bwd (S4D_NN_L2NORM_BWD): with
// n = |x[:, s]| and d = n + eps, dx = dy / d - x (x . dy) / (n d^2) (the second term 0 where n = 0).
#define S4D_NN_L2NORM_EPS 1e-7
#define S4D_B_L2N_X 0   // [c, samples]
#define S4D_B_L2N_Y 1   // [c, samples] (bwd: dy, read)
#define S4D_B_L2N_DX 2  // bwd only: [c, samples], written

// nn_patchnce: PatchNCE's cross-entropy per row i of the scores P[i, j] = q_i . k_j ([s, s],
// attention_scores): the positive logit is the diagonal P[i, i] / tau, the negatives P[i, j] / tau
// for j != i (the diagonal masked out of them), target the positive. That is the cross-entropy of
// row i of P / tau with target i: loss[i] = logsumexp_j(P[i, j] / tau) - P[i, i] / tau. Writes
// loss[i] and grad[i, j] = scale (softmax_j(P[i, :] / tau) - [i == j]) / tau, the gradient of
// scale * sum_i loss[i] w.r.t. P, its diagonal as -(the other entries' shares): 1 - softmax_i
// would cancel when the positive dominates (float, logits up to 2 / tau apart). One invocation per
// row, looping over it four times.
#define S4D_B_PNCE_SCORES 0  // [s, s]
#define S4D_B_PNCE_GRAD 1    // [s, s], written
#define S4D_B_PNCE_LOSS 2    // [s], written

S4D_NAMESPACE_BEGIN

// Push constants of nn_ccpl_gather(_bwd) and nn_l2norm_cols(_bwd).
struct NnCcplParams {
  uint channels;
  uint plane;    // values per channel of the features (gather only)
  uint samples;  // columns
  uint _pad0;
};

// Push constants of nn_patchnce.
struct NnPatchNceParams {
  uint samples;
  float inv_tau;
  float scale;
  uint _pad0;
};

S4D_NAMESPACE_END

#endif  // S4D_NN_CCPL_H
