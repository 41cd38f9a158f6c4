#include "s4d/nn/adain_net.h"

#include "s4d/nn/layers.h"

namespace s4d::nn {

AdainNet::AdainNet(engine::Context& ctx, const io::SafetensorsFile& vgg, const io::SafetensorsFile& decoder,
                   const VggWidths& widths)
    : encoder_(ctx, vgg, 4, widths), decoder_(ctx, decoder, widths) {}

engine::Buffer AdainNet::style(engine::Recorder& rec, const Tensor& style) const {
  return mean_std(rec, encoder_.encode(rec, style, 4));
}

Tensor AdainNet::stylize(engine::Recorder& rec, const Tensor& content, const engine::Buffer& style, float alpha) const {
  const Tensor features = encoder_.encode(rec, content, 4);
  return decoder_.decode(rec, adain(rec, features, mean_std(rec, features), style, alpha));
}

}  // namespace s4d::nn
