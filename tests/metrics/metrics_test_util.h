// Images for the metric tests: constant colours, a seeded LCG pattern (the same generator as
// uiqm_reference.py), and smooth analytic textures.
#pragma once
#include <cmath>
#include <cstdint>
#include <functional>

#include "s4d/io/image_io.h"

namespace s4d::test {

inline io::ImageF constant_image(int w, int h, float r, float g, float b) {
  io::ImageF im{w, h, 3, {}};
  im.data.reserve(size_t(w) * h * 3);
  for (int i = 0; i < w * h; ++i) im.data.insert(im.data.end(), {r, g, b});
  return im;
}

// Levels (state >> 16) % 256 of the LCG state = state * 1103515245 + 12345 mod 2^31, row-major, RGB.
inline io::ImageF lcg_image(int w, int h, uint32_t seed = 12345) {
  io::ImageF im{w, h, 3, std::vector<float>(size_t(w) * h * 3)};
  uint64_t state = seed;
  for (float& v : im.data) {
    state = (state * 1103515245ull + 12345ull) % (1ull << 31);
    v = float((state >> 16) % 256) / 255.0f;
  }
  return im;
}

// RGB image with value f(x, y, c) at each pixel.
inline io::ImageF image_of(int w, int h, const std::function<double(double, double, int)>& f) {
  io::ImageF im{w, h, 3, std::vector<float>(size_t(w) * h * 3)};
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c) im.data[(size_t(y) * w + x) * 3 + c] = float(f(x, y, c));
  return im;
}

// A smooth, textured, non-periodic pattern in [0.1, 0.9] for flow and warp tests.
inline double texture(double x, double y, int c) {
  return 0.5 + 0.2 * std::sin(0.31 * x + 0.17 * y + c) + 0.2 * std::cos(0.23 * y - 0.11 * x + 2.0 * c) * std::sin(0.05 * x);
}

}  // namespace s4d::test
