// PyTorch's bicubic interpolation weights (upsample_bicubic2d without antialiasing: Keys' cubic
// convolution with A = -0.75), shared by DINO's position-embedding resize and MUSIQ's image scales.
#pragma once
#include <array>

namespace s4d::nn {

// The weights of the taps at floor(src) - 1, floor(src), floor(src) + 1, floor(src) + 2 for the
// fraction t = src - floor(src).
inline std::array<double, 4> torch_cubic_weights(double t) {
  constexpr double a = -0.75;
  const auto near = [](double x) { return ((a + 2) * x - (a + 3)) * x * x + 1; };
  const auto far = [](double x) { return ((a * x - 5 * a) * x + 8 * a) * x - 4 * a; };
  return {far(t + 1), near(t), near(1 - t), far(2 - t)};
}

}  // namespace s4d::nn
