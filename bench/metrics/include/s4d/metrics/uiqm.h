// UIQM (Panetta et al. 2016): c1 UICM + c2 UISM + c3 UIConM with c1 = 0.0282, c2 = 0.2953,
// c3 = 3.5753. Higher is better. There is no canonical implementation (METRICS.md 1); two are
// offered, both scoring the frame as 8-bit levels (each value rounded to v * 255, as the references
// read PNG files) at its own size (FUnIE-GAN's measure_uiqm.py resizes to 256x256 first; we do not).
//
// Variant A (default), FUnIE-GAN Evaluation/uqim_utils.py, Python-3 port: levels as float 0..255.
//   UICM: RG = R - G, YB = (R + G)/2 - B; alpha-trimmed mean with T_L = ceil(0.1 K), T_R = floor(0.1 K)
//   summing sorted indices T_L+1 .. K-T_R-1 (the script's off-by-one) divided by K - T_L - T_R;
//   variance over all K values about that mean; UICM = -0.0268 |mu| + 0.1586 sqrt(s2_RG + s2_YB).
//   UISM: per channel scipy-style Sobel (half-sample symmetric border), magnitude scaled to max 255,
//   times the channel; EME over 10x10 blocks (remainder cropped), ln(max/min) skipping blocks with a
//   zero min or max, weight 2 / (floor(W/10) floor(H/10)); lambdas 0.299, 0.587, 0.144 (the script's
//   typo of 0.114). A flat channel (Sobel max 0, NaN in the script) has an all-zero edge map: EME 0.
//   UIConM: 10x10 blocks over all 3 channels, (top/bot) ln(top/bot) with top = max - min,
//   bot = max + min, skipping zeros; times -1 / ((W/10) (H/10)) with real-valued W/10 and H/10 (the
//   Python-3 port; the Python-2 original divides by integers).
// Variant B, xueleichen PSNR-SSIM-UCIQE-UIQM-Python nevaluate.py (needs scikit-image < 0.18):
//   uint8 arithmetic as the script does it: R - G and R + G wrap modulo 256. UICM: T = floor(0.1 K)
//   trimmed from both ends, mean and variance over the trimmed values. UISM: scikit-image 0.17 Sobel
//   (kernels / 4, magnitude / sqrt(2), border pixels 0) on the [0, 1] channel, times the level,
//   rounded half to even to uint8; EME over 8x8 blocks (ceil counts, the last block takes the
//   remainder), zero min or max replaced by 1, weight 2 / (nx ny); lambdas 0.299, 0.587, 0.114.
//   UIConM: logAMEE over 8x8 blocks of gray = 0.2125 R + 0.7154 G + 0.0721 B in [0, 1] with the PLIP
//   operators (gamma = k = 1026); an all-black block (0/0, NaN in the script) is skipped.
#pragma once
#include <vector>

#include "s4d/io/image_io.h"

namespace s4d::metrics {

enum class UiqmVariant { a_funie, b_xueleichen };

inline constexpr double kUiqmC1 = 0.0282, kUiqmC2 = 0.2953, kUiqmC3 = 3.5753;

struct UiqmParts {
  double uicm = 0, uism = 0, uiconm = 0;
  double uiqm() const { return kUiqmC1 * uicm + kUiqmC2 * uism + kUiqmC3 * uiconm; }
};

// Throws std::invalid_argument when the image is not RGB or smaller than 10x10 (variant A needs one
// whole 10x10 block; both variants need 10 values to trim).
UiqmParts uiqm_parts(const io::ImageF& image, UiqmVariant variant = UiqmVariant::a_funie);

inline double uiqm(const io::ImageF& image, UiqmVariant variant = UiqmVariant::a_funie) {
  return uiqm_parts(image, variant).uiqm();
}

namespace detail {
// Planes of 8-bit levels, each [H, W] row-major, from an RGB image in [0, 1].
struct LevelPlanes {
  int width = 0, height = 0;
  std::vector<double> c[3];
};
UiqmParts uiqm_funie_gan(const LevelPlanes& p);
UiqmParts uiqm_xueleichen(const LevelPlanes& p);
}  // namespace detail

}  // namespace s4d::metrics
