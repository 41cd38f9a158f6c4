// The VGG19 "normalised" encoder up to relu5_1 (AdaIN's vgg_normalised.pth, ALGORITHMS.md 4.2) and
// the decoder that mirrors it up to relu4_1 (AdaIN's decoder.pth; MCCNet and HGST share it).
// Weights keep the nn.Sequential state-dict names ("0.weight", "2.weight", ...).
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "s4d/engine/context.h"
#include "s4d/engine/recorder.h"
#include "s4d/io/safetensors.h"
#include "s4d/nn/layers.h"
#include "s4d/nn/tensor.h"

namespace s4d::nn {

// Channels of relu1_1 .. relu5_1. The published networks use VGG19's; tests shrink them.
struct VggWidths {
  std::array<uint32_t, 5> level = {64, 128, 256, 512, 512};
};

// [3, H, W] -> relu<level>_1 has size ceil(H / 2^(level-1)) x ceil(W / 2^(level-1)) (ceil-mode pooling).
uint32_t pooled_size(uint32_t size, int level);

class VggEncoder {
 public:
  // Loads the convolutions up to relu<levels>_1 (1..5); the file's later layers are not read.
  VggEncoder(engine::Context& ctx, const io::SafetensorsFile& file, int levels, const VggWidths& widths = {});

  // relu<level>_1 of an RGB image [3, H, W] in [0, 1] (the first 1x1 convolution holds VGG's
  // mean/255 preprocessing); level 1..levels().
  Tensor encode(engine::Recorder& rec, const Tensor& rgb, int level) const;
  // relu1_1 .. relu<levels>_1 of one pass (AdaAttN's encode_with_intermediate).
  std::vector<Tensor> encode_all(engine::Recorder& rec, const Tensor& rgb) const;
  int levels() const { return levels_; }
  uint32_t channels(int level) const { return widths_.level[level - 1]; }

 private:
  struct Step {
    ConvWeights conv;    // empty name: a 2x2 max pool
    int ends_level = 0;  // relu<ends_level>_1 is this step's output
  };
  std::vector<Step> steps_;
  int levels_;
  VggWidths widths_;
};

class VggDecoder {
 public:
  VggDecoder(engine::Context& ctx, const io::SafetensorsFile& file, const VggWidths& widths = {});

  // relu4_1-shaped features [c4, h, w] -> image [3, 8h, 8w], no output activation.
  Tensor decode(engine::Recorder& rec, const Tensor& features) const;

 private:
  struct Step {
    ConvWeights conv;
    bool relu = true;
    bool upsample_after = false;
  };
  std::vector<Step> steps_;
};

}  // namespace s4d::nn
