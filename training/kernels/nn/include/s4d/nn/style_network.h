// A feed-forward arbitrary-style network as the frame stylizers drive it: what it needs of the
// style image is computed once, then each content image is stylized on its own.
#pragma once
#include <vector>

#include "s4d/engine/recorder.h"
#include "s4d/nn/tensor.h"

namespace s4d::nn {

// What a network keeps of a style image: its tensors, in an order the network defines.
using StyleCode = std::vector<Tensor>;

class StyleNetwork {
 public:
  virtual ~StyleNetwork() = default;
  // What the network keeps of a style image [3, h, w] in [0, 1].
  virtual StyleCode style(engine::Recorder& rec, const Tensor& style) const = 0;
  // The stylized image [3, 8 ceil(H/8), 8 ceil(W/8)] of a content image [3, H, W] in [0, 1], values
  // not clamped; alpha blends the content's and the style's features (1: the full style).
  virtual Tensor stylize(engine::Recorder& rec, const Tensor& content, const StyleCode& style,
                         float alpha) const = 0;
};

}  // namespace s4d::nn
