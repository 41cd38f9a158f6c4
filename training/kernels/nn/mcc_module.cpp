#include "s4d/nn/mcc_module.h"

#include <stdexcept>

#include "s4d/nn/weights.h"

namespace s4d::nn {

MccModule::MccModule(engine::Context& ctx, const io::SafetensorsFile& mcc, uint32_t channels)
    : f_(load_conv(ctx, mcc, "MCCN.f", channels, channels, 1)),
      g_(load_conv(ctx, mcc, "MCCN.g", channels, channels, 1)),
      out_conv_(load_conv(ctx, mcc, "MCCN.out_conv", channels, channels, 1)),
      fc_(load_linear(ctx, mcc, "MCCN.fc", channels, channels)) {}

Tensor MccModule::channel_weights(engine::Recorder& rec, const Tensor& features) const {
  const Tensor g = conv1x1(rec, normalise(rec, features, mean_std(rec, features)), g_, false);
  return conv1x1(rec, squares_over_sum(rec, g), fc_, false);
}

Tensor MccModule::transform(engine::Recorder& rec, const Tensor& fc, const engine::Buffer& style, float alpha) const {
  Tensor c = conv1x1(rec, normalise(rec, fc, mean_std(rec, fc)), f_, false);
  if (alpha == 1.0f) {
    scale_channels(rec, c, style);
  } else {
    Tensor w_style = make_tensor(rec.context(), "style weights", fc.c, 1, 1);
    rec.copy(style, w_style.buffer, w_style.count() * sizeof(float));
    rec.barrier();
    scale_channels(rec, c, blend(rec, w_style, channel_weights(rec, fc), alpha).buffer);
  }
  Tensor fcs = make_tensor(rec.context(), "mcc", fc.c, fc.h, fc.w);
  rec.copy(fc.buffer, fcs.buffer, fc.count() * sizeof(float));
  rec.barrier();
  conv1x1_accumulate(rec, c, out_conv_, fcs);  // the residual on the un-normalised content features
  return fcs;
}

namespace {

Tensor copy_of(engine::Recorder& rec, const Tensor& x, const char* name) {
  Tensor y = make_tensor(rec.context(), name, x.c, x.h, x.w);
  rec.copy(x.buffer, y.buffer, x.count() * sizeof(float));
  rec.barrier();
  return y;
}

}  // namespace

MccTape MccModule::forward(engine::Recorder& rec, const Tensor& fc, const Tensor& fs) const {
  MccTape t;
  t.content_stats = mean_std(rec, fc);
  t.content_norm = normalise(rec, fc, t.content_stats);
  t.c_hat = conv1x1(rec, t.content_norm, f_, false);
  t.style_stats = mean_std(rec, fs);
  t.style_norm = normalise(rec, fs, t.style_stats);
  t.g_hat = conv1x1(rec, t.style_norm, g_, false);
  t.a = squares_over_sum(rec, t.g_hat);
  t.w = conv1x1(rec, t.a, fc_, false);
  t.weighted = copy_of(rec, t.c_hat, "mcc weighted");
  scale_channels(rec, t.weighted, t.w.buffer);
  t.out = copy_of(rec, fc, "mcc");
  conv1x1_accumulate(rec, t.weighted, out_conv_, t.out);
  return t;
}

void MccModule::backward(engine::Recorder& rec, const MccTape& t, const Tensor& dout, std::span<ConvGrads> grads) const {
  if (grads.size() != 4) throw std::invalid_argument("MccModule::backward: needs 4 gradient sets, got " + std::to_string(grads.size()));
  conv_backward_weights(rec, t.weighted, dout, out_conv_, grads[2], true);
  Tensor d_weighted = conv_backward_input(rec, dout, out_conv_);
  // dw_k = sum_p d_weighted_k(p) C_k(p): the second half of the channel sums.
  const engine::Buffer sums = channel_dots(rec, d_weighted, t.c_hat);
  Tensor dw = make_tensor(rec.context(), "mcc dw", t.w.c, 1, 1);
  rec.copy(sums, dw.buffer, dw.count() * sizeof(float), dw.count() * sizeof(float), 0);
  rec.barrier();
  scale_channels(rec, d_weighted, t.w.buffer);  // now dL/dC
  conv_backward_weights(rec, t.content_norm, d_weighted, f_, grads[0], true);
  conv_backward_weights(rec, t.a, dw, fc_, grads[3], true);
  const Tensor da = conv_backward_input(rec, dw, fc_);
  const Tensor dg = squares_over_sum_backward(rec, t.g_hat, da);
  conv_backward_weights(rec, t.style_norm, dg, g_, grads[1], true);
}

std::array<std::pair<std::string, const ConvWeights*>, 4> MccModule::parameters() const {
  return {{{"MCCN.f", &f_}, {"MCCN.g", &g_}, {"MCCN.out_conv", &out_conv_}, {"MCCN.fc", &fc_}}};
}

}  // namespace s4d::nn
