// The VGG19 "normalised" encoder up to relu5_1 (AdaIN's vgg_normalised.pth, ALGORITHMS.md 4.2) and
// the decoder that mirrors it up to relu4_1 (AdaIN's decoder.pth; MCCNet and HGST share it).
// Weights keep the nn.Sequential state-dict names ("0.weight", "2.weight", ...).
#pragma once
#include <array>
#include <span>
#include <string>
#include <utility>
#include <cstdint>
#include <vector>

#include "s4d/engine/context.h"
#include "s4d/engine/recorder.h"
#include "s4d/io/safetensors.h"
#include "s4d/nn/layers.h"
#include "s4d/nn/layers_grad.h"
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

  // Training (the encoder's weights stay fixed). Every step's output of one pass: the 1x1
  // convolution's, then each 3x3 convolution's after its ReLU or each pool's; relu<l>_1 is
  // tape[level_step(l)].
  std::vector<Tensor> forward_tape(engine::Recorder& rec, const Tensor& rgb) const;
  size_t level_step(int level) const;
  // dL/d(rgb) of a forward_tape pass given dL/d(relu<l>_1) in level_grads[l - 1] (an empty tensor:
  // none; at least one given). The gradients are consumed (ReLU masks apply in place).
  Tensor backward(engine::Recorder& rec, const std::vector<Tensor>& tape, std::vector<Tensor> level_grads) const;

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

  // Training. decode keeping each convolution's output (after its ReLU) and each upsampling's;
  // tape.back() is the image.
  std::vector<Tensor> forward_tape(engine::Recorder& rec, const Tensor& features) const;
  // dL/d(features) of a forward_tape pass from `features` given dL/d(image); adds the weight
  // gradients to grads (one per parameters() entry).
  Tensor backward(engine::Recorder& rec, const Tensor& features, const std::vector<Tensor>& tape, const Tensor& dimage,
                  std::span<ConvGrads> grads) const;
  // The convolutions in order with their state-dict prefixes ("1", "5", ...).
  std::vector<std::pair<std::string, const ConvWeights*>> parameters() const;

 private:
  struct Step {
    ConvWeights conv;
    bool relu = true;
    bool upsample_after = false;
    std::string prefix;  // the state-dict prefix
  };
  std::vector<Step> steps_;
};

}  // namespace s4d::nn
