// The network layers on the GPU (kernels in shaders/nn, twins in training/ref/.../nn_ref.h). Each
// call records one dispatch followed by a barrier, so its result is ready for the next layer, and
// returns a new tensor unless it says otherwise. Shape errors throw std::invalid_argument naming
// the layer and the shapes, before anything is recorded.
#pragma once
#include <cstdint>
#include <span>
#include <string>

#include "s4d/engine/buffer.h"
#include "s4d/engine/recorder.h"
#include "s4d/nn/tensor.h"

namespace s4d::nn {

// One Conv2d (k = 1..16: up to a ViT's 16x16 patches) or Linear (k = 1) layer's parameters on the device.
struct ConvWeights {
  std::string name;  // for messages and buffer names, e.g. "vgg_normalised.safetensors 2"
  uint32_t cin = 0, cout = 0, k = 1;
  engine::Buffer weight;  // [cout, cin, k, k]
  engine::Buffer bias;    // [cout]
};

// One LayerNorm(channels) layer's parameters on the device.
struct NormWeights {
  std::string name;
  uint32_t channels = 0;
  engine::Buffer weight;  // [channels]
  engine::Buffer bias;    // [channels]
};

// Throws std::invalid_argument when the value counts do not match the shape.
NormWeights upload_norm(engine::Context& ctx, const std::string& name, uint32_t channels, std::span<const float> weight,
                        std::span<const float> bias);

// Throws std::invalid_argument when the value counts do not match the shape.
ConvWeights upload_conv(engine::Context& ctx, const std::string& name, uint32_t cin, uint32_t cout, uint32_t k,
                        std::span<const float> weight, std::span<const float> bias);

// ReflectionPad2d(1) + Conv2d(k=3) (+ ReLU). Needs H, W >= 2, as PyTorch's reflection padding does.
Tensor conv3x3(engine::Recorder& rec, const Tensor& x, const ConvWeights& w, bool relu);
// Conv2d(k=3, padding=1) (+ ReLU): zero padding, as torchvision's VGG; any H, W >= 1.
Tensor conv3x3_zero_pad(engine::Recorder& rec, const Tensor& x, const ConvWeights& w, bool relu);
// Conv2d(k, stride, padding) with zero padding (+ ReLU), any k: [cout, (h + 2 pad - k) / stride + 1, ...].
// Needs cin * k * k <= S4D_NN_MAX_LOOP (kernel nn_conv_strided).
Tensor conv_strided(engine::Recorder& rec, const Tensor& x, const ConvWeights& w, uint32_t stride, uint32_t pad, bool relu);
// F.unfold(x, k, padding=pad, stride): [c k k, (h + 2 pad - k) / stride + 1, ...], row (ci k + ky) k + kx
// holding tap (ky, kx) of channel ci, 0 in the padding; conv1x1 of it with the weights [cout, c k k]
// is conv_strided (faster on lavapipe for large inputs). Needs H, W + 2 pad >= k.
Tensor im2col(engine::Recorder& rec, const Tensor& x, uint32_t k, uint32_t stride, uint32_t pad);
// Conv2d(k=1) (+ ReLU); a Linear layer when x is [in, 1, 1].
Tensor conv1x1(engine::Recorder& rec, const Tensor& x, const ConvWeights& w, bool relu);
// out += Conv2d(k=1)(x): a residual connection into `out`.
void conv1x1_accumulate(engine::Recorder& rec, const Tensor& x, const ConvWeights& w, Tensor& out);
void relu_inplace(engine::Recorder& rec, Tensor& x);
// MaxPool2d(2, 2, ceil_mode=True): [c, ceil(h/2), ceil(w/2)].
Tensor maxpool2(engine::Recorder& rec, const Tensor& x);
// AvgPool2d(3, 1) (no padding): [c, h - 2, w - 2]; needs H, W >= 3.
Tensor avgpool3(engine::Recorder& rec, const Tensor& x);
// MaxPool2d(2, 2) (floor mode, torchvision's VGG): [c, floor(h/2), floor(w/2)]; needs H, W >= 2.
Tensor maxpool2_floor(engine::Recorder& rec, const Tensor& x);
// AvgPool2d(2) (floor mode, CLIP's ModifiedResNet): [c, floor(h/2), floor(w/2)]; needs H, W >= 2.
Tensor avgpool2(engine::Recorder& rec, const Tensor& x);
// MaxPool2d(3, 2, pad) (floor mode; pad 0: torchvision's AlexNet, pad 1: ResNet's stem):
// [c, (h + 2 pad - 3) / 2 + 1, (w + 2 pad - 3) / 2 + 1]; pad is 0 or 1, H, W >= 3 - 2 pad.
Tensor maxpool3s2(engine::Recorder& rec, const Tensor& x, uint32_t pad = 0);
// DISTS's L2pooling(filter_size=5, stride=2): sqrt(conv(x^2, [1 2 1]^T [1 2 1] / 16, stride 2,
// zero padding 1) + 1e-12) per channel: [c, ceil(h/2), ceil(w/2)].
Tensor l2pool(engine::Recorder& rec, const Tensor& x);
// x[c, 2 y, 2 x]: [c, ceil(h / 2), ceil(w / 2)]; conv1x1 of it is Conv2d(k=1, stride=2).
Tensor subsample2(engine::Recorder& rec, const Tensor& x);
// Upsample(scale_factor=2, mode='nearest').
Tensor upsample2(engine::Recorder& rec, const Tensor& x);

// [2, c]: per-channel means, then sqrt(unbiased variance + eps) (AdaIN's calc_mean_std). Needs H*W >= 2.
engine::Buffer mean_std(engine::Recorder& rec, const Tensor& x, float eps = 1e-5f);
// AdaptiveAvgPool2d(1): [c, 1, 1], the per-channel means of mean_std (its buffer also holds the
// standard deviations, after the means). Needs H*W >= 2.
Tensor global_average(engine::Recorder& rec, const Tensor& x);
// [c, 1, 1]: sum(x^2) / sum(x) per channel (MCC's style weighting). Needs H*W >= 2.
Tensor squares_over_sum(engine::Recorder& rec, const Tensor& x);
// alpha (sigma_s (x - mu_c) / sigma_c + mu_s) + (1 - alpha) x, with stats from mean_std.
Tensor adain(engine::Recorder& rec, const Tensor& x, const engine::Buffer& content_stats,
             const engine::Buffer& style_stats, float alpha);
// (x - mu) / sigma (MCC's normal()).
Tensor normalise(engine::Recorder& rec, const Tensor& x, const engine::Buffer& stats);
// x[c, :] *= factors[c], in place.
void scale_channels(engine::Recorder& rec, Tensor& x, const engine::Buffer& factors);
// alpha a + (1 - alpha) b, both of a's shape.
Tensor blend(engine::Recorder& rec, const Tensor& a, const Tensor& b, float alpha);
// a + b, both of a's shape.
Tensor add(engine::Recorder& rec, const Tensor& a, const Tensor& b);
// a - b, both of a's shape.
Tensor subtract(engine::Recorder& rec, const Tensor& a, const Tensor& b);
// LayerNorm over the channels of every pixel: a transformer's tokens, [c, 1, n]. Needs c <= S4D_NN_MAX_LOOP.
Tensor layernorm(engine::Recorder& rec, const Tensor& x, const NormWeights& w, float eps);
// GELU (exact, erf) in place.
void gelu_inplace(engine::Recorder& rec, Tensor& x);
// A vision transformer's tokens [c, 1, 1 + gh gw]: pos [c, 1, 1 + gh gw] (the class token folded into
// its first column) plus, from the second column on, the patch embeddings [c, gh, gw] in row-major order.
// pos [c, 1, 1]: the first token only, no position embedding (kernel nn_prepend_token; CLIP-IQA's
// attention pooling, whose first token is the spatial mean).
Tensor vit_embed(engine::Recorder& rec, const Tensor& patches, const Tensor& pos);
// Nearest-neighbour resize to out_h x out_w: PyTorch's interpolate(size=...) default mode, source
// index floor(dst * in / out) (exact integers here; see nn_resize_nearest.comp).
Tensor resize_nearest(engine::Recorder& rec, const Tensor& x, uint32_t out_h, uint32_t out_w);
// torch.cat(parts, dim=1) of tensors of one size, by buffer copies.
Tensor concat_channels(engine::Recorder& rec, std::span<const Tensor* const> parts);

}  // namespace s4d::nn
