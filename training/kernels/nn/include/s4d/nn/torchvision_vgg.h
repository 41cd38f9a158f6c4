// torchvision's VGG16 / VGG19 `features` (Conv2d 3x3 with zero padding 1, ReLU, MaxPool2d(2, 2) in
// floor mode), the backbone of LPIPS-VGG (VGG16), of DISTS (VGG16 with every max pool replaced by
// an L2 pool) and of the Gram style loss's torchvision option (VGG19). Weights keep torchvision's state-dict names: "features.<i>.weight" [cout, cin, 3, 3]
// and "features.<i>.bias", i the module index in `features` (vgg16-397923af.pth, vgg19-dcbb9e9d.pth);
// only the convolutions up to the last tap are read. The caller normalises the input.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "s4d/engine/context.h"
#include "s4d/engine/recorder.h"
#include "s4d/io/safetensors.h"
#include "s4d/nn/layers.h"
#include "s4d/nn/tensor.h"
#include "s4d/nn/vgg.h"

namespace s4d::nn {

enum class TorchVggDepth { vgg16, vgg19 };
// What replaces features' MaxPool2d(2, 2): itself (floor mode), or DISTS's L2 pooling (l2pool()).
enum class TorchVggPool { max, l2 };

class TorchVgg {
 public:
  // `taps`: module indices of the ReLUs whose outputs features() returns, increasing (LPIPS-VGG:
  // 3, 8, 15, 22, 29 = relu1_2 .. relu5_3). `widths.level[b]` is block b's width (tests shrink them).
  TorchVgg(engine::Context& ctx, const io::SafetensorsFile& file, TorchVggDepth depth, std::vector<int> taps,
           const VggWidths& widths = {}, TorchVggPool pool = TorchVggPool::max);

  // The taps' outputs for a normalised image [3, H, W]. Throws std::invalid_argument when the image
  // is smaller than min_size() (a 2x2 pooling of a single row or column) or not RGB.
  std::vector<Tensor> features(engine::Recorder& rec, const Tensor& x) const;
  uint32_t tap_channels(size_t tap) const { return tap_channels_.at(tap); }
  size_t tap_count() const { return tap_channels_.size(); }
  // Smallest side the taps can be computed for: 2^(max pools before the last tap); 1 with L2 pools.
  uint32_t min_size() const { return min_size_; }

 private:
  struct Step {
    ConvWeights conv;  // empty name: a 2x2 max pool
    bool tap = false;  // the ReLU after this convolution is a tap
  };
  std::vector<Step> steps_;
  std::vector<uint32_t> tap_channels_;
  uint32_t min_size_ = 1;
  TorchVggPool pool_;
};

}  // namespace s4d::nn
