// CLIP's ResNet image tower (Radford et al. 2021, "ModifiedResNet" of openai/CLIP model.py, which
// pyiqa's archs/clip_model.py keeps; RN50 for CLIP-IQA+, METRICS.md 2): a stem of three 3x3
// convolutions (3 -> w/2 stride 2, w/2 -> w/2, w/2 -> w, zero padding 1, each with BatchNorm and
// ReLU) and AvgPool2d(2); four layers of Bottlenecks (resnet_bottleneck.h, strided by average
// pooling) of widths w, 2w, 4w, 8w, the last three striding; then AttentionPool2d: the tokens are the
// map's spatial mean followed by its positions (row-major), multi-head attention of the mean token's
// query over all tokens (heads of 64 channels: 32w / 64 heads, q scaled by 1/8 with its bias), and the
// output projection c_proj. The position embedding is not added: pyiqa's CLIPIQA calls the tower with
// pos_embedding=False (its default), so images of any size go in unresized and
// visual.attnpool.positional_embedding is never read.
//
// Weights keep CLIP's state-dict names: visual.conv{1,2,3}.weight, visual.bn{1,2,3}.*,
// visual.layer<L>.<i>.{conv1,bn1,conv2,bn2,conv3,bn3,downsample.0,downsample.1}.*,
// visual.attnpool.{q,k,v,c}_proj.{weight,bias}; the width w is conv3's output channels, each layer's
// block count the blocks present (RN50: w = 64, [3, 4, 6, 3], 1024 outputs). BatchNorm is folded into
// the convolutions as they load (weights.h load_conv_bn; CLIP keeps PyTorch's eps 1e-5).
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "s4d/engine/context.h"
#include "s4d/io/safetensors.h"
#include "s4d/nn/layers.h"
#include "s4d/nn/resnet_bottleneck.h"
#include "s4d/nn/tensor.h"

namespace s4d::nn {

class ClipResnet {
 public:
  // Smallest side: the stem's stride and four average poolings leave a map of floor(side / 32) or so;
  // each pooling needs 2 rows and columns (31 -> 16 -> 8 -> 4 -> 2 -> 1).
  static constexpr uint32_t kMinSize = 31;

  // Throws std::runtime_error naming the file and tensor when one is missing or wrongly shaped.
  ClipResnet(engine::Context& ctx, const io::SafetensorsFile& file);

  uint32_t output_dim() const { return c_proj_.cout; }
  const std::array<uint32_t, 4>& blocks() const { return blocks_; }
  uint32_t width() const { return width_; }
  uint32_t heads() const { return heads_; }

  // The image feature ([output_dim] values, not normalised) of a normalised image [3, H, W], H, W >=
  // kMinSize; throws std::invalid_argument on other shapes, or when layer4's map has a single position.
  std::vector<float> features(const Tensor& image) const;

 private:
  engine::Context& ctx_;
  uint32_t width_ = 0, heads_ = 0;
  std::array<uint32_t, 4> blocks_{};
  ConvWeights stem_[3];
  std::array<std::vector<Bottleneck>, 4> layers_;
  ConvWeights q_proj_, k_proj_, v_proj_, c_proj_;  // q_proj pre-scaled by 1 / sqrt(64)
};

}  // namespace s4d::nn
