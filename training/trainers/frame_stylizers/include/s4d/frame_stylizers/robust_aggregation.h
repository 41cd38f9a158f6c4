// Robust patch aggregation of Elad & Milanfar 2017, "Style Transfer via Texture Synthesis", step
// (b): given target patches z_p placed at positions p of an image, find the image X minimising
//   sum_p || R_p X - z_p ||^r        (R_p extracts the patch at p; r < 2 down-weights outliers)
// by iteratively reweighted least squares: with w_p = max(|| R_p X - z_p ||, eps)^(r - 2) from the
// current X, X becomes the w-weighted average of the patch values covering each pixel.
#pragma once
#include <vector>

#include "s4d/io/image_io.h"

namespace s4d::frame_stylizers {

struct PlacedPatch {
  int x = 0, y = 0;              // top-left corner in the image
  const float* values = nullptr;  // [n, n, C] row-major, C = the image's channels
};

struct AggregationSettings {
  float r = 0.8f;     // the robust norm's exponent (the paper's 0.8)
  int iterations = 3;  // IRLS steps; the first uses the weights of `current`
  // Distances below eps are clamped to it so an exactly matching patch gets a large, finite weight
  // (eps = 1e-3 is 1/4 level of 255 over one pixel).
  float eps = 1e-3f;
};

// Returns the aggregate; pixels no patch covers keep `current`'s values. Throws
// std::invalid_argument for a patch outside the image, a null patch or a non-positive size.
io::ImageF robust_aggregate(const io::ImageF& current, int patch_size, const std::vector<PlacedPatch>& patches,
                            const AggregationSettings& settings);

}  // namespace s4d::frame_stylizers
