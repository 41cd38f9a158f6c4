// AdaIN (Huang & Belongie 2017, naoto0804/pytorch-AdaIN test.py): decode(alpha-blended
// adain(relu4_1(content), relu4_1(style))), with vgg_normalised and decoder weights.
#pragma once
#include "s4d/engine/buffer.h"
#include "s4d/engine/context.h"
#include "s4d/engine/recorder.h"
#include "s4d/io/safetensors.h"
#include "s4d/nn/tensor.h"
#include "s4d/nn/vgg.h"

namespace s4d::nn {

class AdainNet {
 public:
  AdainNet(engine::Context& ctx, const io::SafetensorsFile& vgg, const io::SafetensorsFile& decoder,
           const VggWidths& widths = {});

  // The style's relu4_1 statistics [2, c4], computed once per style image [3, h, w].
  engine::Buffer style_stats(engine::Recorder& rec, const Tensor& style) const;
  // The stylized image [3, 8 ceil(H/8), 8 ceil(W/8)] of a content image [3, H, W] (values not clamped).
  Tensor stylize(engine::Recorder& rec, const Tensor& content, const engine::Buffer& style_stats, float alpha) const;

 private:
  VggEncoder encoder_;
  VggDecoder decoder_;
};

}  // namespace s4d::nn
