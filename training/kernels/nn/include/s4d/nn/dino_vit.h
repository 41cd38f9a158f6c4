// DINO's vision transformer (Caron et al. 2021; facebookresearch/dino vision_transformer.py, the
// ViT of Dosovitskiy et al. 2021 without a head): a PxP stride-P patch convolution, a class token,
// learned position embeddings, `depth` pre-norm blocks x += proj(MHSA(LayerNorm(x))),
// x += fc2(GELU(fc1(LayerNorm(x)))), a final LayerNorm; the output is the class token. LayerNorms
// use eps 1e-6, the attention softmax((q k^T) / sqrt(head_dim)) with qkv bias, GELU the exact erf.
// Weights keep DINO's state-dict names (dino_vitbase16_pretrain.pth): cls_token [1, 1, D],
// pos_embed [1, 1 + g^2, D], patch_embed.proj.weight [D, 3, P, P] / .bias, blocks.<i>.norm1,
// blocks.<i>.attn.qkv [3D, D], blocks.<i>.attn.proj [D, D], blocks.<i>.norm2, blocks.<i>.mlp.fc1
// [M, D], blocks.<i>.mlp.fc2 [D, M], norm. Width D, patch P, grid g, depth and M come from the
// shapes; the head count is not stored, so it is given (DINO's ViTs all have 64-wide heads).
// Tokens live as [D, 1, N] tensors (layers.h: 1x1 convolutions are the Linear layers).
#pragma once
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include "s4d/engine/context.h"
#include "s4d/io/safetensors.h"
#include "s4d/nn/attention.h"
#include "s4d/nn/layers.h"
#include "s4d/nn/tensor.h"

namespace s4d::nn {

inline constexpr float kVitNormEps = 1e-6f;
inline constexpr uint32_t kVitHeadWidth = 64;  // DINO ViT-S/B: 384 / 6, 768 / 12

struct VitShape {
  uint32_t width = 0, depth = 0, heads = 0, patch = 0, grid = 0, hidden = 0;
};

// DINO's interpolate_pos_encoding on the host, in double: the position embedding for an image of
// image_h x image_w pixels as [width, 1 + gh gw] (gh = image_h / patch, gw = image_w / patch), the
// class token added to column 0. The stored g x g grid is kept when gh gw = g^2 and the image is
// square; otherwise it is resized bicubically (PyTorch's interpolate, A = -0.75, border clamped,
// align_corners False) with scale factors ((gh + 0.1) / g, (gw + 0.1) / g), source coordinates
// (dst + 0.5) / scale - 0.5, as DINO calls it. `pos` is [1 + g^2, width] and `cls` [width] as stored.
std::vector<double> dino_position_embedding(const std::vector<float>& pos, const std::vector<float>& cls,
                                            const VitShape& shape, uint32_t image_h, uint32_t image_w);

class DinoVit {
 public:
  // heads 0: width / kVitHeadWidth. Throws std::runtime_error naming the file and tensor when one is
  // missing or wrongly shaped, and std::invalid_argument when the shapes do not make a ViT the
  // kernels can run (a width the heads do not divide, a non-square position grid, widths past
  // S4D_NN_MAX_LOOP).
  DinoVit(engine::Context& ctx, const io::SafetensorsFile& file, uint32_t heads = 0);

  const VitShape& shape() const { return shape_; }
  // The class token after the final LayerNorm ([width] values) for a normalised image [3, H, W],
  // H, W >= patch (the last H % patch rows and W % patch columns are not seen, as the convolution).
  std::vector<float> cls(const Tensor& image) const;

 private:
  const Tensor& position(uint32_t image_h, uint32_t image_w) const;  // cached per image size

  engine::Context& ctx_;
  VitShape shape_;
  std::vector<float> pos_, cls_;  // as stored
  ConvWeights patch_;
  std::vector<TransformerBlock> blocks_;
  NormWeights norm_;
  mutable std::map<std::pair<uint32_t, uint32_t>, Tensor> positions_;
};

}  // namespace s4d::nn
