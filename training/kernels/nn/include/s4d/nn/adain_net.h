// AdaIN (Huang & Belongie 2017, naoto0804/pytorch-AdaIN test.py): decode(alpha-blended
// adain(relu4_1(content), relu4_1(style))), with vgg_normalised and decoder weights.
#pragma once
#include "s4d/engine/context.h"
#include "s4d/io/safetensors.h"
#include "s4d/nn/style_network.h"
#include "s4d/nn/vgg.h"

namespace s4d::nn {

class AdainNet final : public StyleNetwork {
 public:
  AdainNet(engine::Context& ctx, const io::SafetensorsFile& vgg, const io::SafetensorsFile& decoder,
           const VggWidths& widths = {});

  // The style's relu4_1 statistics [2, c4, 1].
  StyleCode style(engine::Recorder& rec, const Tensor& style) const override;
  Tensor stylize(engine::Recorder& rec, const Tensor& content, const StyleCode& style, float alpha) const override;

 private:
  VggEncoder encoder_;
  VggDecoder decoder_;
};

}  // namespace s4d::nn
