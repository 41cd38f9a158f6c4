// MUSIQ's network (Ke et al., ICCV 2021; pyiqa archs/musiq_arch.py, the port of
// google-research/musiq; METRICS.md 3). Every 32x32 patch of the multi-scale input (metrics/musiq.h)
// goes on its own through a ResNet root: StdConv(3, 64, 7, stride 2, TF 'SAME' padding 2 / 3),
// GroupNorm(32, 64, eps 1e-6), ReLU, 'SAME' MaxPool(3, 2) (padding 0 / 1), and one Bottleneck
// 64 -> 256 (StdConv 1x1, 3x3, 1x1 of width 64, each with GroupNorm(32, eps 1e-4), ReLU after the
// first two; a StdConv 1x1 projection with GroupNorm on the identity; ReLU of the sum), to an
// [8, 8, 256] map that `embedding` = Linear(16384, width) reads in (row, column, channel) order.
// The tokens get the hashed spatial embedding position_emb[position] and the scale embedding
// scale_emb[scale]; a class token `cls` goes first; `depth` pre-norm blocks (LayerNorm eps 1e-6,
// separate query / key / value Linear layers with biases, softmax(q k^T / sqrt(head width)), `out`,
// MLP fc1, exact GELU, fc2), encoder_norm, and the head Linear(width, 1) on the class token give the
// score (num_class 1: the KonIQ and PaQ-2-PiQ checkpoints; dist_to_mos is then the identity).
// StdConv's weight standardisation, w := (w - mean) / (std + 1e-5) per output channel (std unbiased,
// over cin k k), is done once on the host when the weights load (in double).
//
// The patches run as one tall tensor: patch p sits at rows 36 p + 2 .. 36 p + 33, columns 2 .. 33 of a
// [3, 36 n + 2, 36] mosaic whose other values are 0, so the symmetric padding-2 stride-2 7x7
// convolution sees each patch with the 'SAME' zero padding (2 before, 3 after) and puts its 16x16
// output at rows 18 p + 1 .., columns 1 ..; nn_group_norm normalises each cell's window and zeroes
// the rest, so the padding-1 3x3 max pool and the zero-padded 3x3 convolution see the same zeros;
// after the pool a cell is 9x9 with the 8x8 map at rows and columns 1 .. 8. The embedding is a 9x9
// stride-9 convolution whose row and column 0 weights are zero. Convolutions of k > 1 run as
// nn_im2col and a 1x1 convolution, and 1x1 convolutions on the maps flattened to one row (the tiled
// kernels' fast paths). Patches run in chunks of kChunk so no tensor passes the storage-buffer range
// (the bottleneck's 3x3 im2col, [576, 9 kChunk, 9], is the largest: 96 MB).
//
// Weights: pyiqa's state-dict names (musiq_koniq_ckpt-e95806b9.pth, musiq_paq2piq_ckpt-364c0c84.pth):
// conv_root.weight [64, 3, 7, 7], gn_root.{weight,bias}, block1.{conv1,conv2,conv3,conv_proj}.weight,
// block1.{gn1,gn2,gn3,gn_proj}.{weight,bias}, embedding.{weight,bias} [width, 16384],
// transformer_encoder.{posembed_input.position_emb [1, g^2, width], scaleembed_input.scale_emb
// [scales, width], cls [1, 1, width], encoder_norm}, transformer_encoder.transformer.encoderblock_<i>.
// {norm1, attention.{query,key,value,out}, norm2, mlp.{fc1,fc2}}, head.{weight [1, width], bias}.
#pragma once
#include <cstdint>
#include <vector>

#include "s4d/engine/context.h"
#include "s4d/io/safetensors.h"
#include "s4d/nn/attention.h"
#include "s4d/nn/layers.h"
#include "s4d/nn/tensor.h"

namespace s4d::nn {

struct MusiqShape {
  uint32_t width = 0, depth = 0, heads = 0, hidden = 0, grid = 0, scales = 0;
};

// One patch of the multi-scale input: 3 x 32 x 32 values ([-1, 1] image, 0 for TF 'SAME' padding),
// its hashed position (row * grid + column) and its scale index.
struct MusiqPatches {
  std::vector<float> pixels;  // [n, 3, 32, 32]
  std::vector<uint32_t> position, scale;  // [n] each
};

class MusiqNet {
 public:
  static constexpr uint32_t kPatch = 32;
  static constexpr uint32_t kChunk = 512;  // patches per pass of the ResNet root

  // heads 0: width / 64 (pyiqa's MUSIQ: 384 / 6). Throws std::runtime_error naming the file and tensor
  // when one is missing or wrongly shaped, and std::invalid_argument when the shapes make no MUSIQ.
  MusiqNet(engine::Context& ctx, const io::SafetensorsFile& file, uint32_t heads = 0);

  const MusiqShape& shape() const { return shape_; }
  // The head's output for the patches (at least one; positions < grid^2, scales < scales).
  double score(const MusiqPatches& patches) const;

 private:
  Tensor root(const std::vector<float>& pixels, uint32_t first, uint32_t count) const;  // [width, count, 1]

  engine::Context& ctx_;
  MusiqShape shape_;
  ConvWeights conv_root_, conv1_, conv2_, conv3_, conv_proj_, embedding_;
  NormWeights gn_root_, gn1_, gn2_, gn3_, gn_proj_, encoder_norm_;
  std::vector<float> position_emb_, scale_emb_, cls_, head_weight_;  // as stored
  float head_bias_ = 0;
  std::vector<TransformerBlock> blocks_;
};

}  // namespace s4d::nn
