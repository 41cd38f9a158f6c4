// PSNR as 3DGS reports it: values in [0, 1], mean squared error over all pixels and all channels,
// PSNR = 10 log10(1 / MSE) in dB. Higher is better. The one PSNR of the project: the trainer's test
// views (train/evaluate.h) and Style4D-Bench's `psnr` (bench/report/frames_eval.cpp) both score with
// it. It does not clamp: values outside [0, 1] count as they are. Neither caller needs a clamp here:
// the evaluator clamps each render to [0, 1] itself (the same image feeds its SSIM and saved PNG, as
// in 3DGS), and the bench scores frames decoded from 8-bit files, which are in [0, 1] already.
#pragma once
#include "s4d/io/image_io.h"

namespace s4d::io {

// The MSE is floored at kPsnrMinMse, so identical images score kPsnrCapDb instead of infinity (JSON
// has no infinity). 8-bit frames of 1 Mpixel differing in one level of one value have MSE 5e-12, so
// the floor only touches near-identical images.
inline constexpr double kPsnrMinMse = 1e-10;
inline constexpr double kPsnrCapDb = 100.0;

// Throws std::invalid_argument("psnr: ...") when the images differ in width, height or channels,
// or hold no values or not width * height * channels of them.
double psnr(const ImageF& image, const ImageF& reference);

}  // namespace s4d::io
