// AdaAttN (Liu et al. 2021, Huage001/AdaAttN, the released --shallow_layer --skip_connection_3
// model): attention-weighted per-point mean and std at relu3_1, relu4_1 and relu5_1 with keys from
// the normalised shallower levels, the transformer's merge of relu4_1 and relu5_1, and the decoder
// with the relu3_1 skip connection. Weights (docs/stylization.md, "Network stylizers"): vgg_normalised, and
// net_adaattn_3, net_transformer and net_decoder keeping AdaAttN's state-dict names.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "s4d/engine/context.h"
#include "s4d/io/safetensors.h"
#include "s4d/nn/layers.h"
#include "s4d/nn/style_network.h"
#include "s4d/nn/vgg.h"

namespace s4d::nn {

// One AdaAttN module: f, g (keys, key_planes wide) and h (values, in_planes wide), 1x1 convolutions.
class AdaattnModule {
 public:
  AdaattnModule(engine::Context& ctx, const io::SafetensorsFile& file, const std::string& prefix, uint32_t in_planes,
                uint32_t key_planes);

  // The style side, {K = g(key), V = h(features)}, over at most max_sample style positions: larger
  // maps are first resized (nearest) to the largest grid of their aspect with at most max_sample
  // positions, a deterministic stand-in for PyTorch's seeded randperm sample (which cannot be
  // reproduced). The 1x1 convolutions commute with that subsampling.
  StyleCode style(engine::Recorder& rec, const Tensor& features, const Tensor& key, uint32_t max_sample) const;
  // S * norm(content) + M, with the attention of f(content_key) over the style's keys.
  Tensor apply(engine::Recorder& rec, const Tensor& content, const Tensor& content_key, const Tensor& style_k,
               const Tensor& style_v) const;

 private:
  ConvWeights f_, g_, h_;
};

// The key of level `last` (0-based, relu<last+1>_1): the normalised levels 0..last, the shallower
// ones resized (nearest) to its size first, concatenated along channels (AdaAttN's get_key).
Tensor adaattn_key(engine::Recorder& rec, const std::vector<Tensor>& levels, int last);

class AdaattnNet final : public StyleNetwork {
 public:
  // 64 x 64 style positions, AdaAttN's --max_sample default.
  static constexpr uint32_t kMaxSample = 64 * 64;

  // widths.level[3] == widths.level[4] (the transformer adds relu4_1's and relu5_1's outputs).
  AdaattnNet(engine::Context& ctx, const io::SafetensorsFile& vgg, const io::SafetensorsFile& adaattn_3,
             const io::SafetensorsFile& transformer, const io::SafetensorsFile& decoder, const VggWidths& widths = {},
             uint32_t max_sample = kMaxSample);

  // {K, V} of relu3_1, relu4_1 and relu5_1 in that order.
  StyleCode style(engine::Recorder& rec, const Tensor& style) const override;
  // alpha < 1 blends each module's output with its content features, as AdaIN's test.py does.
  Tensor stylize(engine::Recorder& rec, const Tensor& content, const StyleCode& style, float alpha) const override;

 private:
  VggEncoder encoder_;
  AdaattnModule attn_3_, attn_4_, attn_5_;
  ConvWeights merge_conv_;
  std::vector<ConvWeights> decoder_;  // decoder_layer_1.1, then decoder_layer_2's convolutions
  uint32_t max_sample_;
};

}  // namespace s4d::nn
