// DISTS (Ding et al. 2020, dingkeyan93/DISTS DISTS_pt.py = pyiqa dists_arch.py; METRICS.md 5):
// stage 0 is the raw RGB input in [0, 1]; stages 1..5 are torchvision VGG16 relu1_2, relu2_2,
// relu3_3, relu4_3, relu5_3 of the ImageNet-normalised input, every max pool replaced by an L2 pool
// (GPU). Per stage k and channel c, over the whole map (population statistics, host, double):
//   S1 = (2 mu_x mu_y + c1) / (mu_x^2 + mu_y^2 + c1), S2 = (2 cov_xy + c2) / (var_x + var_y + c2),
// c1 = c2 = 1e-6, and DISTS = 1 - sum_k sum_c (alpha_kc S1 + beta_kc S2), alpha and beta divided
// by sum(alpha) + sum(beta). No resize (pyiqa's convention; the original CLI shrinks to a shorter
// side of 256). Symmetric, 0 for identical images, lower is better.
// Weights: torchvision vgg16-397923af.pth ("features.<i>") and DISTS_pytorch/weights.pt ("alpha",
// "beta", [1, 1475, 1, 1] each), converted to safetensors.
#pragma once
#include <array>
#include <vector>

#include "s4d/engine/context.h"
#include "s4d/io/image_io.h"
#include "s4d/io/safetensors.h"
#include "s4d/nn/torchvision_vgg.h"
#include "s4d/util/chw.h"

namespace s4d::metrics {

inline constexpr std::array<int, 5> kDistsTaps = {3, 8, 15, 22, 29};  // VGG16 relu1_2 .. relu5_3
inline constexpr double kDistsC1 = 1e-6, kDistsC2 = 1e-6;

// One image's stages: the raw input, then the five taps, [C, H, W] in double.
using DistsFeatures = std::vector<util::Chw<double>>;

// 1 - sum (alpha S1 + beta S2) with alpha, beta already normalised, one entry per channel of all
// stages in order. Throws std::invalid_argument when shapes or counts differ.
double dists_from_features(const DistsFeatures& x, const DistsFeatures& y, const std::vector<double>& alpha,
                           const std::vector<double>& beta);

class Dists {
 public:
  // Throws std::runtime_error naming the file and tensor when a weight is missing or wrongly shaped.
  Dists(engine::Context& ctx, const io::SafetensorsFile& vgg16, const io::SafetensorsFile& alpha_beta,
        const nn::VggWidths& widths = {});

  DistsFeatures features(const io::ImageF& rgb) const;
  double distance(const DistsFeatures& x, const DistsFeatures& y) const { return dists_from_features(x, y, alpha_, beta_); }
  double operator()(const io::ImageF& x, const io::ImageF& y) const { return distance(features(x), features(y)); }

 private:
  engine::Context& ctx_;
  nn::TorchVgg vgg_;
  std::vector<double> alpha_, beta_;
};

}  // namespace s4d::metrics
