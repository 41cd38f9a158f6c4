// CKDN's network (Zheng et al., ICCV 2021; pyiqa archs/ckdn_arch.py, the port of researchmm/CKDN;
// METRICS.md 8): two ResNet-50 stems with their own weights, one for the restored image x ("qse")
// and one for the degraded reference y ("dte"), each Conv2d(3, 64, 7, stride 2, padding 3, no bias,
// no BatchNorm or ReLU after it), MaxPool2d(3, 2, padding 1) and torchvision's layer1 (3 Bottlenecks,
// 256 channels). Their difference (x - y) goes through layer2 ("csp": 4 Bottlenecks, 512 channels,
// the stride 2 in the first block's 3x3 convolution, as torchvision's ResNet v1.5; stride-2
// convolutions run as subsample2 of, or before, the tiled stride-1 kernels), a global average
// and the MLP fc_ = Linear(512, 2048), ReLU, Linear(2048, 2048), ReLU, Linear(2048, 1) (dropout off);
// the score is the sigmoid of that logit (host). aux_csp and fc1_ are in the checkpoint but not in
// the forward pass.
//
// Weights: pyiqa's state-dict names ("net.qse_1.weight", "net.qse_2.<i>.conv1.weight",
// "net.qse_2.<i>.bn1.{weight,bias,running_mean,running_var}", "net.qse_2.0.downsample.{0,1}.*",
// "net.dte_*", "net.csp.*", "net.fc_.{0,3,6}.{weight,bias}"), as tools/convert_weights.py ckdn
// writes them. BatchNorm runs in eval mode, so it is folded into the convolution before it when the
// weights load (weights.h load_conv_bn); the Bottlenecks are resnet_bottleneck.h's, strided as torchvision's.
#pragma once
#include <cstdint>
#include <vector>

#include "s4d/engine/context.h"
#include "s4d/engine/recorder.h"
#include "s4d/io/safetensors.h"
#include "s4d/nn/layers.h"
#include "s4d/nn/resnet_bottleneck.h"
#include "s4d/nn/tensor.h"

namespace s4d::nn {

class CkdnNet {
 public:
  // Smallest side: layer2's map, ceil(side / 8), needs 2 values per channel for the global average.
  static constexpr uint32_t kMinSize = 9;

  // Throws std::runtime_error naming the file and tensor when one is missing or wrongly shaped.
  CkdnNet(engine::Context& ctx, const io::SafetensorsFile& file);

  // The logit ([1, 1, 1], before the sigmoid) of a normalised restored image x and degraded
  // reference y, both [3, H, W] of one size; throws std::invalid_argument on other shapes.
  Tensor logit(engine::Recorder& rec, const Tensor& x, const Tensor& y) const;

 private:
  Tensor stem(engine::Recorder& rec, const Tensor& x, const ConvWeights& conv, const std::vector<Bottleneck>& layer1) const;

  ConvWeights qse_1_, dte_1_;
  std::vector<Bottleneck> qse_2_, dte_2_, csp_;
  ConvWeights fc_[3];
};

}  // namespace s4d::nn
