#include "s4d/nn/mcc_net.h"

namespace s4d::nn {

MccNet::MccNet(engine::Context& ctx, const io::SafetensorsFile& vgg, const io::SafetensorsFile& decoder,
               const io::SafetensorsFile& mcc, const VggWidths& widths)
    : encoder_(ctx, vgg, 4, widths), decoder_(ctx, decoder, widths), mcc_(ctx, mcc, widths.level[3]) {}

StyleCode MccNet::style(engine::Recorder& rec, const Tensor& style) const {
  StyleCode code;
  code.push_back(mcc_.channel_weights(rec, encoder_.encode(rec, style, 4)));
  return code;
}

Tensor MccNet::stylize(engine::Recorder& rec, const Tensor& content, const StyleCode& style, float alpha) const {
  return decoder_.decode(rec, mcc_.transform(rec, encoder_.encode(rec, content, 4), style.at(0).buffer, alpha));
}

}  // namespace s4d::nn
