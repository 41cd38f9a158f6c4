// The MCCNet/HGST training loss (diyiiyiii/MCCNet net.py and HGST, ALGORITHMS.md 4.5) for
// one content/style pair, forward and backward on the GPU: with F_l = relu<l>_1 of the fixed VGG
// encoder, Ics = Dec(MCC(Fc_4, Fs_4)), Icc = Dec(MCC(Fc_4, Fc_4)), Iss = Dec(MCC(Fs_4, Fs_4)),
// Ics_N = Dec(MCC(F_4(content + noise), Fs_4)) and MSE the mean squared error,
//   content   = sum_{l in content levels} MSE(norm(F_l(Ics)), norm(F_l(content)))
//   style     = sum_{l in style levels} MSE(mu(F_l(Ics)), mu(F_l(style))) + MSE(sigma(F_l(Ics)), sigma(F_l(style)))
//   identity1 = MSE(Icc, content) + MSE(Iss, style)
//   identity2 = sum_{l = 1..5} MSE(F_l(Icc), F_l(content)) + MSE(F_l(Iss), F_l(style))
//   noise     = MSE(Ics_N, Ics), neither side detached (the illumination loss)
//   tv        = sum |Ics[.., y, x] - Ics[.., y, x + 1]| + |Ics[.., y, x] - Ics[.., y + 1, x]| (a sum)
//   selfsim   = HGST's "Iins" on v = avgpool3(F_5(Ics)): the mean over channels of
//               mean_i min_j (1 - v_i v_j / |v|^2) (s4d_nn_grad.h)
//   ccpl      = sum over the CCPL levels l of CCPL(F_l(Ics), F_l(content)) (ccpl.h: CCPL's or HGST's
//               jittered "LCL" variant, the content side fixed)
// total = the weighted sum.
#pragma once
#include <array>
#include <vector>

#include "s4d/engine/recorder.h"
#include "s4d/nn/ccpl.h"
#include "s4d/nn/layers_grad.h"
#include "s4d/nn/mcc_module.h"
#include "s4d/nn/vgg.h"

namespace s4d::nn {

// The relu<l>_1 levels of the content and style terms: MCCNet's (content 4, 5; style 1..5) or
// HGST's (content 3, 4, 5; style 5, 2, 3, 4, 5: relu5_1 counted twice, relu1_1 not at all).
struct MccLossLevels {
  std::vector<int> content = {4, 5};
  std::vector<int> style = {1, 2, 3, 4, 5};
  static MccLossLevels mccnet() { return {}; }
  static MccLossLevels hgst() { return {{3, 4, 5}, {5, 2, 3, 4, 5}}; }
};

// HGST's weights (ALGORITHMS.md 4.5).
struct MccLossWeights {
  float content = 3.0f, style = 18.0f, identity1 = 70.0f, identity2 = 1.0f, noise = 3000.0f, tv = 1e-4f, selfsim = 1.0f,
        ccpl = 4.0f;
};

// The terms' values, unweighted, and the weighted total.
struct MccLossValues {
  double content = 0, style = 0, identity1 = 0, identity2 = 0, noise = 0, tv = 0, selfsim = 0, ccpl = 0, total = 0;
};

// Recorded loss terms: partial sums (squared errors, TV) with the factor that turns each into its term.
class MccLossRecord {
 public:
  enum Term { content, style, identity1, identity2, noise, tv, selfsim, ccpl };
  void add(Term term, engine::Buffer partials, double factor);
  // After the recording ran.
  MccLossValues values(engine::Context& ctx, const MccLossWeights& weights) const;

 private:
  struct Part {
    Term term;
    engine::Buffer partials;
    double factor;
  };
  std::vector<Part> parts_;
};

// The networks the loss runs through: the fixed encoder (5 levels), the decoder and MCC module
// being trained, and their gradients (decoder convolutions in parameters() order, then MCC's).
struct MccTrainee {
  const VggEncoder& encoder;
  const VggDecoder& decoder;
  const MccModule& mcc;
};
struct MccGrads {
  std::vector<ConvGrads> decoder;
  std::vector<ConvGrads> mcc;  // f, g, out_conv, fc
};

// The CCPL term's inputs for one pair: the variant, one head per level of config.levels, the
// samples drawn on each level (the caller's seeded generator: draw_ccpl_samples), and where the
// heads are trained their gradients (first, second per level), added to. No heads: no term (0).
struct MccCcplInputs {
  CcplConfig config;
  const std::vector<CcplHead>* heads = nullptr;
  std::vector<CcplSamples> samples;
  std::vector<ConvGrads>* head_grads = nullptr;
};

// Zeroed gradients for the trainee's parameters.
MccGrads zero_mcc_grads(engine::Recorder& rec, const MccTrainee& net);

// Records the loss of one pair of RGB images [3, H, W] in [0, 1] (H, W multiples of 8, at least
// 40: relu5_1 of 3x3 for the 3x3 pool) and adds its gradients to grads. content_noise is the content plus Gaussian noise (MCCNet
// and HGST draw sigma ~ U(0.01, 0.02) per step), the same size.
MccLossRecord record_mcc_loss(engine::Recorder& rec, const MccTrainee& net, const Tensor& content, const Tensor& style,
                              const Tensor& content_noise, const MccLossLevels& levels, const MccLossWeights& weights,
                              const MccCcplInputs& ccpl, MccGrads& grads);

}  // namespace s4d::nn
