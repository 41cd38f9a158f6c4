// LPIPS v0.1 (Zhang et al. 2018, richzhang/PerceptualSimilarity; METRICS.md 9) with the VGG16 or
// AlexNet backbone: RGB in [0, 1] -> 2x - 1 -> the scaling layer (x - shift) / scale -> torchvision
// VGG16 `features` (taps relu1_2, relu2_2, relu3_3, relu4_3, relu5_3) or AlexNet `features` (taps
// relu1..relu5) on the GPU; per tap and pixel the channel vector is unit-normalised
// (f / (sqrt(sum_c f^2) + 1e-10)); the distance is sum over taps of the spatial mean of
// sum_c w_c (na_c - nb_c)^2, w the lin heads. The head runs on the host in double (it is O(C H W),
// against the backbone's O(C^2 H W)). Symmetric; 0 for identical images; lower is better.
// Weights: torchvision's vgg16-397923af.pth or alexnet-owt-7be5be79.pth ("features.<i>.weight/bias")
// and LPIPS's weights/v0.1/vgg.pth or alex.pth ("lin<l>.model.1.weight" [1, C_l, 1, 1]), converted
// to safetensors.
#pragma once
#include <array>
#include <memory>
#include <optional>
#include <vector>

#include "s4d/engine/context.h"
#include "s4d/io/image_io.h"
#include "s4d/io/safetensors.h"
#include "s4d/nn/torchvision_alexnet.h"
#include "s4d/nn/torchvision_vgg.h"
#include "s4d/util/chw.h"

namespace s4d::metrics {

// LPIPS's ScalingLayer (v0.1): (x - shift) / scale on inputs in [-1, 1].
inline constexpr std::array<float, 3> kLpipsShift = {-0.030f, -0.088f, -0.188f};
inline constexpr std::array<float, 3> kLpipsScale = {0.458f, 0.448f, 0.450f};
inline constexpr double kLpipsEps = 1e-10;  // normalize_tensor's eps, added to the norm
// torchvision VGG16 `features` indices of relu1_2, relu2_2, relu3_3, relu4_3, relu5_3.
inline constexpr std::array<int, 5> kLpipsVggTaps = {3, 8, 15, 22, 29};

// One image's taps, each channel vector unit-normalised, [C, H, W] in double.
using LpipsFeatures = std::vector<util::Chw<double>>;

// The LPIPS head on normalised taps: sum_l mean_{h,w} sum_c lin[l][c] (a_l - b_l)^2. Throws
// std::invalid_argument when the taps' shapes or the head widths differ.
double lpips_head(const LpipsFeatures& a, const LpipsFeatures& b, const std::vector<std::vector<double>>& lin);

// Unit-normalises every pixel's channel vector in place (LPIPS's normalize_tensor).
void normalise_channels(util::Chw<double>& f);

enum class LpipsNet { vgg, alex };
// What the scaling layer receives: 2x - 1 of the [0, 1] frame (richzhang's lpips, pyiqa: the
// published convention), or the [0, 1] frame itself (the 3DGS-style lpipsPyTorch that Style4D's
// authors' metrics.py calls; METRICS.md 9 asks to expose both).
enum class LpipsInput { signed_unit, unit };

class Lpips {
 public:
  // `widths`: the backbone's five tap widths (tests shrink them); nullopt: the published ones.
  // Throws std::runtime_error naming the file and tensor when a weight is missing or wrongly shaped.
  Lpips(engine::Context& ctx, const io::SafetensorsFile& backbone, const io::SafetensorsFile& heads, LpipsNet net,
        const std::optional<std::array<uint32_t, 5>>& widths = std::nullopt, LpipsInput input = LpipsInput::signed_unit);

  // The normalised taps of an RGB image in [0, 1]; at least 16x16 (VGG: relu5_3 follows 4 poolings)
  // or 31x31 (AlexNet).
  LpipsFeatures features(const io::ImageF& rgb) const;
  double distance(const LpipsFeatures& a, const LpipsFeatures& b) const { return lpips_head(a, b, lin_); }
  double operator()(const io::ImageF& a, const io::ImageF& b) const { return distance(features(a), features(b)); }
  LpipsNet net() const { return net_; }

 private:
  engine::Context& ctx_;
  LpipsNet net_;
  LpipsInput input_;
  std::unique_ptr<nn::TorchVgg> vgg_;
  std::unique_ptr<nn::TorchAlexNet> alex_;
  std::vector<std::vector<double>> lin_;
};

}  // namespace s4d::metrics
