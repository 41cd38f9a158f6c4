// SSIM in the 3DGS convention (METRICS.md 10 A; graphdeco's utils/loss_utils.py `ssim`, which the
// Style4D authors' code uses): RGB in [0, 1], data range 1 (C1 = 0.01^2, C2 = 0.03^2), 11x11 Gaussian
// window with sigma 1.5 (1-D weights exp(-(i-5)^2 / 4.5) normalised, outer product), each channel
// filtered on its own with zero padding 5 (output the input's size), population moments, and the
// mean of the SSIM map over every pixel, borders included, and all 3 channels. Higher is better; 1
// for identical images. Computed in double (the reference computes in float32).
#pragma once
#include <vector>

#include "s4d/io/image_io.h"

namespace s4d::metrics {

inline constexpr int kSsimWindow = 11;
inline constexpr double kSsimSigma = 1.5;
inline constexpr double kSsimC1 = 0.01 * 0.01;
inline constexpr double kSsimC2 = 0.03 * 0.03;

// The normalised 1-D Gaussian weights, 11 values.
std::vector<double> ssim_window_1d();

// The SSIM map, [H, W, 3] row-major. Throws std::invalid_argument when the images are not RGB or
// differ in size.
std::vector<double> ssim_map(const io::ImageF& a, const io::ImageF& b);

// Mean of ssim_map: the `content_ssim` metric when a is the stylised frame and b the original.
double ssim(const io::ImageF& a, const io::ImageF& b);

}  // namespace s4d::metrics
