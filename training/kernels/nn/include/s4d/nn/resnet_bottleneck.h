// ResNet's Bottleneck block (He et al. 2016) in its two published forms, BatchNorm folded into the
// convolutions as the weights load (weights.h load_conv_bn): out = ReLU(bn3(conv3(s(ReLU(bn2(conv2(
// ReLU(bn1(conv1(x))))))))) + identity(x)), conv1 1x1 to `planes`, conv2 3x3 (zero padding 1), conv3
// 1x1 to 4 planes, identity x or the "downsample" 1x1 + BatchNorm when the block strides or changes
// the width. Where the stride goes:
//   conv     torchvision's v1.5 (CKDN): in conv2 and in the downsample convolution, [ceil(h/2), ...];
//            run as nn_subsample2 of the stride-1 conv2 and before the downsample's conv1x1.
//   avgpool  CLIP's ModifiedResNet (model.py, "anti-aliased"): AvgPool2d(stride) after conv2's ReLU
//            and before the downsample convolution, [floor(h/2), ...].
// Weights keep the state-dict names "<layer>.<i>.conv1.weight", "<layer>.<i>.bn1.{weight, bias,
// running_mean, running_var}", ..., "<layer>.<i>.downsample.{0,1}.*" (both publish the same names).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "s4d/engine/context.h"
#include "s4d/engine/recorder.h"
#include "s4d/io/safetensors.h"
#include "s4d/nn/layers.h"
#include "s4d/nn/tensor.h"

namespace s4d::nn {

enum class BottleneckStride { conv, avgpool };

struct Bottleneck {
  ConvWeights conv1, conv2, conv3, downsample;  // BatchNorm folded in; downsample.cout == 0: none
  uint32_t stride = 1;                          // 1 or 2
};

// torchvision's and CLIP's _make_layer: `blocks` Bottlenecks of width `planes`, the first taking the
// stride and the downsample (it strides or cin != 4 planes). Throws std::runtime_error naming the
// file and tensor when one is missing or wrongly shaped, std::invalid_argument for a stride past 2.
std::vector<Bottleneck> load_bottleneck_layer(engine::Context& ctx, const io::SafetensorsFile& file,
                                              const std::string& prefix, uint32_t cin, uint32_t planes, uint32_t blocks,
                                              uint32_t stride);

// One block on x [cin, H, W]; an avgpool block that strides needs H, W >= 2.
Tensor run_bottleneck(engine::Recorder& rec, const Tensor& x, const Bottleneck& b, BottleneckStride style);

}  // namespace s4d::nn
