// MCCNet (Deng et al. 2021, diyiiyiii/MCCNet) and HGST, which keeps its architecture with its own
// weights (ALGORITHMS.md 4.2): decode(MCC(relu4_1(content), relu4_1(style))), the MCC module in
// mcc_module.h.
#pragma once
#include "s4d/engine/context.h"
#include "s4d/io/safetensors.h"
#include "s4d/nn/layers.h"
#include "s4d/nn/mcc_module.h"
#include "s4d/nn/style_network.h"
#include "s4d/nn/vgg.h"

namespace s4d::nn {

class MccNet final : public StyleNetwork {
 public:
  MccNet(engine::Context& ctx, const io::SafetensorsFile& vgg, const io::SafetensorsFile& decoder,
         const io::SafetensorsFile& mcc, const VggWidths& widths = {});

  // The style's channel weights w = fc(a) [c4, 1, 1].
  StyleCode style(engine::Recorder& rec, const Tensor& style) const override;
  // alpha < 1 blends with MCC(content, content), as MCCNet's test script does; MCC is affine in w,
  // so this blends the channel weights.
  Tensor stylize(engine::Recorder& rec, const Tensor& content, const StyleCode& style, float alpha) const override;
  // The MCC module alone: Fcs of relu4_1 content features and the style's channel weights.
  Tensor transform(engine::Recorder& rec, const Tensor& content_features, const engine::Buffer& style,
                   float alpha) const {
    return mcc_.transform(rec, content_features, style, alpha);
  }

 private:
  VggEncoder encoder_;
  VggDecoder decoder_;
  MccModule mcc_;
};

}  // namespace s4d::nn
