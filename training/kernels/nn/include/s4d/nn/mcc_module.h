// The MCC module of MCCNet (Deng et al. 2021) and HGST (ALGORITHMS.md 4.2): with norm(F) =
// (F - mu) / sigma per channel (unbiased variance + 1e-5), C = f(norm(Fc)), G = g(norm(Fs)),
// a_k = sum_p G_k(p)^2 / sum_p G_k(p), w = fc(a) and Fcs = Fc + out_conv(C * w). Weights:
// mcc_module.safetensors with the names "MCCN.f.weight", ... ("MCCN.h.*", defined but unused, is
// accepted and not read). Inference (channel_weights, transform) and training (forward keeps what
// backward needs; backward adds the parameter gradients).
#pragma once
#include <array>
#include <span>
#include <string>
#include <utility>

#include "s4d/engine/context.h"
#include "s4d/io/safetensors.h"
#include "s4d/nn/layers.h"
#include "s4d/nn/layers_grad.h"

namespace s4d::nn {

// What one MCC(Fc, Fs) keeps for its backward pass.
struct MccTape {
  engine::Buffer content_stats, style_stats;
  Tensor content_norm, c_hat, style_norm, g_hat, a, w, weighted;  // weighted = C * w
  Tensor out;                                                      // Fcs
};

class MccModule {
 public:
  MccModule(engine::Context& ctx, const io::SafetensorsFile& mcc, uint32_t channels);

  // Inference. The channel weights w = fc(a) [c, 1, 1] of relu4_1 features.
  Tensor channel_weights(engine::Recorder& rec, const Tensor& features) const;
  // Fcs of content features and style channel weights; alpha < 1 blends w with the content's own.
  Tensor transform(engine::Recorder& rec, const Tensor& content_features, const engine::Buffer& style,
                   float alpha) const;

  // Training: MCC(Fc, Fs) keeping its intermediates (tape.out is what transform returns at alpha 1).
  MccTape forward(engine::Recorder& rec, const Tensor& content_features, const Tensor& style_features) const;
  // Adds dL/d(parameters) of dL/d(tape.out) to grads (in parameters() order). Fc and Fs are the
  // fixed encoder's features of fixed images, so no gradient flows to them.
  void backward(engine::Recorder& rec, const MccTape& tape, const Tensor& dout, std::span<ConvGrads> grads) const;
  // f, g, out_conv, fc with their state-dict prefixes ("MCCN.f", ...).
  std::array<std::pair<std::string, const ConvWeights*>, 4> parameters() const;

 private:
  ConvWeights f_, g_, out_conv_, fc_;
};

}  // namespace s4d::nn
