// PSNR as 3DGS reports it: RGB in [0, 1], mean squared error over all pixels and all 3 channels,
// PSNR = 10 log10(1 / MSE) in dB. Higher is better.
#pragma once
#include "s4d/io/image_io.h"

namespace s4d::metrics {

// The MSE is floored at kPsnrMinMse, so identical images score kPsnrCapDb instead of infinity (JSON
// has no infinity). 8-bit frames of 1 Mpixel differing in one level of one value have MSE 5e-12, so
// the floor only touches near-identical images. train::psnr_of scores identical images 100 dB too.
inline constexpr double kPsnrMinMse = 1e-10;
inline constexpr double kPsnrCapDb = 100.0;

// Throws std::invalid_argument when the images are not RGB or differ in size.
double psnr(const io::ImageF& image, const io::ImageF& reference);

}  // namespace s4d::metrics
