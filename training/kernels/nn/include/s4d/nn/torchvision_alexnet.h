// torchvision's AlexNet `features` (IMAGENET1K_V1, alexnet-owt-7be5be79.pth), the backbone of
// LPIPS-Alex: Conv2d(3, 64, 11, stride 4, padding 2), ReLU, MaxPool2d(3, 2), Conv2d(64, 192, 5,
// padding 2), ReLU, MaxPool2d(3, 2), Conv2d(192, 384, 3, padding 1), ReLU, Conv2d(384, 256, 3,
// padding 1), ReLU, Conv2d(256, 256, 3, padding 1), ReLU (the last max pool is not needed). Weights
// "features.{0,3,6,8,10}.weight/bias". The caller normalises the input.
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

// Channels of relu1 .. relu5; tests shrink them.
struct AlexWidths {
  std::array<uint32_t, 5> level = {64, 192, 384, 256, 256};
};

class TorchAlexNet {
 public:
  // Smallest side: relu1 must be at least 7 so that both 3x3 stride-2 pools have an output.
  static constexpr uint32_t kMinSize = 31;

  TorchAlexNet(engine::Context& ctx, const io::SafetensorsFile& file, const AlexWidths& widths = {});

  // relu1 .. relu5 of a normalised image [3, H, W]; throws std::invalid_argument under kMinSize.
  std::vector<Tensor> features(engine::Recorder& rec, const Tensor& x) const;
  uint32_t tap_channels(size_t tap) const { return widths_.level.at(tap); }
  size_t tap_count() const { return 5; }

 private:
  AlexWidths widths_;
  ConvWeights conv_[5];
};

}  // namespace s4d::nn
