#include "s4d/nn/adain_net.h"

#include "s4d/nn/layers.h"

namespace s4d::nn {

AdainNet::AdainNet(engine::Context& ctx, const io::SafetensorsFile& vgg, const io::SafetensorsFile& decoder,
                   const VggWidths& widths)
    : encoder_(ctx, vgg, 4, widths), decoder_(ctx, decoder, widths) {}

StyleCode AdainNet::style(engine::Recorder& rec, const Tensor& style) const {
  StyleCode code(1);
  code[0] = Tensor{mean_std(rec, encoder_.encode(rec, style, 4)), 2, encoder_.channels(4), 1};
  return code;
}

Tensor AdainNet::stylize(engine::Recorder& rec, const Tensor& content, const StyleCode& style, float alpha) const {
  const Tensor features = encoder_.encode(rec, content, 4);
  return decoder_.decode(rec, adain(rec, features, mean_std(rec, features), style.at(0).buffer, alpha));
}

}  // namespace s4d::nn
