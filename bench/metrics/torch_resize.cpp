#include "s4d/metrics/torch_resize.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

#include "s4d/nn/torch_cubic.h"

namespace s4d::metrics {

namespace {

// One output index's four source indices (clamped) and weights.
struct CubicTap {
  std::array<uint32_t, 4> at;
  std::array<double, 4> w;
};

std::vector<CubicTap> cubic_taps(uint32_t in, uint32_t out) {
  const double scale = float(in) / float(out);  // torch's compute_scales_value, in float
  std::vector<CubicTap> taps(out);
  for (uint32_t i = 0; i < out; ++i) {
    const double src = scale * (i + 0.5) - 0.5;
    const double f = std::floor(src);
    taps[i].w = nn::torch_cubic_weights(src - f);
    for (int k = 0; k < 4; ++k)
      taps[i].at[size_t(k)] = static_cast<uint32_t>(std::clamp<int64_t>(int64_t(f) - 1 + k, 0, int64_t{in} - 1));
  }
  return taps;
}

}  // namespace

std::vector<int> torch_nearest_index(int in, int out) {
  const float scale = float(in) / float(out);  // torch's compute_scales_value, in float
  std::vector<int> src(static_cast<size_t>(out));
  for (int i = 0; i < out; ++i) src[size_t(i)] = std::min(int(std::floor(float(i) * scale)), in - 1);
  return src;
}

util::Chw<double> torch_bicubic_resize(const util::Chw<double>& x, uint32_t out_h, uint32_t out_w) {
  if (out_h == 0 || out_w == 0 || x.h == 0 || x.w == 0)
    throw std::invalid_argument("torch_bicubic_resize: " + std::to_string(x.w) + "x" + std::to_string(x.h) + " to " +
                                std::to_string(out_w) + "x" + std::to_string(out_h));
  const std::vector<CubicTap> ty = cubic_taps(x.h, out_h), tx = cubic_taps(x.w, out_w);
  util::Chw<double> rows(x.c, x.h, out_w), y(x.c, out_h, out_w);
  for (uint32_t c = 0; c < x.c; ++c) {
    for (uint32_t r = 0; r < x.h; ++r)
      for (uint32_t i = 0; i < out_w; ++i)
        for (int k = 0; k < 4; ++k) rows.at(c, r, i) += tx[i].w[size_t(k)] * x.at(c, r, tx[i].at[size_t(k)]);
    for (uint32_t j = 0; j < out_h; ++j)
      for (uint32_t i = 0; i < out_w; ++i)
        for (int k = 0; k < 4; ++k) y.at(c, j, i) += ty[j].w[size_t(k)] * rows.at(c, ty[j].at[size_t(k)], i);
  }
  return y;
}

}  // namespace s4d::metrics
