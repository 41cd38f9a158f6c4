#include "s4d/nn/mcc_net.h"

#include "s4d/nn/weights.h"

namespace s4d::nn {

MccNet::MccNet(engine::Context& ctx, const io::SafetensorsFile& vgg, const io::SafetensorsFile& decoder,
               const io::SafetensorsFile& mcc, const VggWidths& widths)
    : encoder_(ctx, vgg, 4, widths),
      decoder_(ctx, decoder, widths),
      f_(load_conv(ctx, mcc, "MCCN.f", widths.level[3], widths.level[3], 1)),
      g_(load_conv(ctx, mcc, "MCCN.g", widths.level[3], widths.level[3], 1)),
      out_conv_(load_conv(ctx, mcc, "MCCN.out_conv", widths.level[3], widths.level[3], 1)),
      fc_(load_linear(ctx, mcc, "MCCN.fc", widths.level[3], widths.level[3])) {}

Tensor MccNet::channel_weights(engine::Recorder& rec, const Tensor& features) const {
  const Tensor g = conv1x1(rec, normalise(rec, features, mean_std(rec, features)), g_, false);
  return conv1x1(rec, squares_over_sum(rec, g), fc_, false);
}

StyleCode MccNet::style(engine::Recorder& rec, const Tensor& style) const {
  StyleCode code;
  code.push_back(channel_weights(rec, encoder_.encode(rec, style, 4)));
  return code;
}

Tensor MccNet::stylize(engine::Recorder& rec, const Tensor& content, const StyleCode& style, float alpha) const {
  return decoder_.decode(rec, transform(rec, encoder_.encode(rec, content, 4), style.at(0).buffer, alpha));
}

Tensor MccNet::transform(engine::Recorder& rec, const Tensor& fc, const engine::Buffer& style, float alpha) const {
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

}  // namespace s4d::nn
