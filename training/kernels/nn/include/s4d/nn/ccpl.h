// CCPL, the contrastive coherence preserving loss (Wu et al. 2022, JarrentWu1031/CCPL net.py), and
// HGST's jittered variant "LCL" (ALGORITHMS.md 4.5), on the GPU: for one level of q = F(Ics) and
// k = F(content) (k fixed), the difference vectors f[:, anchor] - f[:, neighbour] of the sampled
// pairs (each anchor with its 8 neighbours), a projection head Linear(C, C) - ReLU - Linear(C, C / 4)
// on each, L2 normalisation (+1e-7), and PatchNCE with temperature tau: sample i's positive is
// q_i . k_i, its negatives q_i . k_j for the other samples j of the same image; the loss is the mean
// cross-entropy over the samples. Kernels nn_ccpl_gather(_bwd), nn_l2norm_cols(_bwd), nn_patchnce
// (s4d_nn_ccpl.h); the heads, scores and products reuse nn_conv1x1, nn_attn_scores, nn_attn_average
// and nn_transpose. Twins: ref/ccpl_ref.h.
#pragma once
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "s4d/engine/buffer.h"
#include "s4d/engine/recorder.h"
#include "s4d/nn/layers.h"
#include "s4d/nn/layers_grad.h"
#include "s4d/nn/tensor.h"

namespace s4d::nn {

// The variant: which relu<l>_1 levels, how many anchors (num_s), whether each neighbour offset gets
// HGST's random jitter, and whether the heads are trained (CCPL) or stay at their random init (HGST).
struct CcplConfig {
  std::vector<int> levels;
  int anchors = 16;
  bool jitter = true;
  bool train_heads = false;
  float tau = 0.07f;
  // HGST's net.py: relu3_1, relu4_1; num_s 16; jitter; heads not in the optimiser.
  static CcplConfig hgst() { return {{3, 4}, 16, true, false, 0.07f}; }
  // CCPL's train.py defaults: num_l 3 (relu2_1 .. relu4_1), num_s 8; no jitter; heads trained.
  static CcplConfig original() { return {{2, 3, 4}, 8, false, true, 0.07f}; }
};

// The 8 anchors x neighbours sampled on one level: flat indices into its h x w plane, sample
// 8 a + t being anchor a's neighbour t in row-major order of its 3x3 window.
struct CcplSamples {
  std::vector<uint32_t> anchor, neighbour;
};

// `anchors` distinct anchors drawn uniformly from the interior (rows and columns 1 .. size - 2, as
// CCPL's feature_sample); neighbour offsets {-w-1, -w, -w+1, -1, +1, w-1, w, w+1} in flat index,
// each plus an independent U{-1, 0, +1} when jitter, clamped to [0, h w - 1] (HGST). Throws
// std::invalid_argument when the plane is under 3x3 or has fewer interior positions than anchors.
CcplSamples draw_ccpl_samples(uint32_t h, uint32_t w, int anchors, bool jitter, std::mt19937_64& rng);

// One projection head: Linear(C, C) then ReLU then Linear(C, C / 4).
struct CcplHead {
  ConvWeights first, second;
};

// [c, 1, s]: f[:, anchor] - f[:, neighbour]; pairs holds [anchor..., neighbour...] as uint.
Tensor ccpl_gather(engine::Recorder& rec, const Tensor& f, const engine::Buffer& pairs, uint32_t samples);
// df += the adjoint of ccpl_gather applied to dout [c, 1, s].
void ccpl_gather_backward(engine::Recorder& rec, const Tensor& dout, const engine::Buffer& pairs, Tensor& df);
// Each column of x [c, 1, s] divided by its norm + 1e-7.
Tensor l2norm_columns(engine::Recorder& rec, const Tensor& x);
// dx of l2norm_columns given its input x and dy.
Tensor l2norm_columns_backward(engine::Recorder& rec, const Tensor& x, const Tensor& dy);
// PatchNCE on scores [1, s, s] = q_i . k_j: per-row losses (a buffer of s floats) and the gradient
// [1, s, s] of scale * their sum w.r.t. the scores.
struct PatchNce {
  engine::Buffer loss;
  Tensor grad;
};
PatchNce patchnce(engine::Recorder& rec, const Tensor& scores, float tau, float scale);

// Records one level's term weight * mean_i PatchNCE_i: dfq += its gradient w.r.t. q's features and,
// where head_grads is not null (2 entries: first, second), the heads' gradients through q and k are
// added to it (CCPL's k is not detached before its head); weight 0 without head_grads records the
// forward only. Returns the per-sample losses (their sum / s is the unweighted term). Throws std::invalid_argument naming the shapes or index at fault.
engine::Buffer record_ccpl_level(engine::Recorder& rec, const CcplHead& head, const Tensor& fq, const Tensor& fk,
                                 const CcplSamples& samples, float tau, float weight, Tensor& dfq,
                                 ConvGrads* head_grads);

}  // namespace s4d::nn
