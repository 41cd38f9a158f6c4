// The Gram-matrix style loss (Style4D's supplementary "style loss", METRICS.md 11): features F_l
// [C_l, H_l W_l] of VGG19 at relu1_1, relu2_1, relu3_1, relu4_1 and relu5_1 (GPU), Gram matrices
// G_l = F_l F_l^T / (C_l H_l W_l) (host, double), and
//   loss = sum_l mean_{i,j} (G_l(frame)[i, j] - G_l(style)[i, j])^2.
// Lower is better; 0 for identical images. The Gram normalisation makes the frame and the style
// image comparable at any sizes, so the style image is not resized.
// Two VGG19s (METRICS.md asks for both): AdaIN's vgg_normalised (the stylizers' encoder: raw [0, 1]
// RGB, reflection padding, ceil-mode pooling; names "0", "2", ...), or torchvision's vgg19
// ("features.<i>", ImageNet mean/std normalisation, zero padding, floor-mode pooling).
#pragma once
#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "s4d/engine/context.h"
#include "s4d/io/image_io.h"
#include "s4d/io/safetensors.h"
#include "s4d/nn/torchvision_vgg.h"
#include "s4d/metrics/rgb_tensor.h"
#include "s4d/nn/vgg.h"

namespace s4d::metrics {

enum class GramBackbone { vgg_normalised, torchvision_vgg19 };

// torchvision VGG19 `features` indices of relu1_1, relu2_1, relu3_1, relu4_1, relu5_1.
inline constexpr std::array<int, 5> kGramVgg19Taps = {1, 6, 11, 20, 29};

// One image's Gram matrices, [C_l, C_l] row-major per layer.
struct GramSet {
  std::vector<uint32_t> channels;
  std::vector<std::vector<double>> g;
};

// F F^T / (C H W) of features [C, H W] given as floats.
std::vector<double> gram_matrix(const std::vector<float>& features, uint32_t channels, size_t positions);

// sum_l mean (a_l - b_l)^2; throws std::invalid_argument when the layer widths differ.
double gram_loss(const GramSet& a, const GramSet& b);

class GramStyleLoss {
 public:
  // Throws std::runtime_error naming the file and tensor when a weight is missing or wrongly shaped.
  GramStyleLoss(engine::Context& ctx, const io::SafetensorsFile& vgg19, GramBackbone backbone,
                const nn::VggWidths& widths = {});

  // The Gram matrices of an RGB image in [0, 1].
  GramSet grams(const io::ImageF& rgb) const;
  double operator()(const io::ImageF& frame, const io::ImageF& style) const { return gram_loss(grams(frame), grams(style)); }

 private:
  engine::Context& ctx_;
  GramBackbone backbone_;
  std::unique_ptr<nn::VggEncoder> normalised_;
  std::unique_ptr<nn::TorchVgg> torchvision_;
};

}  // namespace s4d::metrics
