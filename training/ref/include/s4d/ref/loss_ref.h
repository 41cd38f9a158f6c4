// CPU twin of the image loss kernels (shaders/loss): (1 - lambda) L1 + lambda (1 - SSIM) with an
// 11x11 Gaussian window (sigma 1.5), zero padding, per channel, the SSIM map averaged; value and
// gradient with respect to the rendered image. Templated on the scalar type.
#pragma once
#include <array>
#include <cmath>
#include <cstddef>
#include <vector>

#include "s4d_loss.h"

namespace s4d::ref {

template <class T>
struct LossValue {
  T loss{}, l1{}, ssim{};  // l1 and ssim are means over all elements
  std::vector<T> grad;     // dL/d image, [H*W*C]
};

namespace detail {

template <class T>
std::array<T, 2 * S4D_SSIM_RADIUS + 1> ssim_taps() {
  const double w[6] = {S4D_SSIM_W0, S4D_SSIM_W1, S4D_SSIM_W2, S4D_SSIM_W3, S4D_SSIM_W4, S4D_SSIM_W5};
  std::array<T, 2 * S4D_SSIM_RADIUS + 1> t{};
  for (int k = -S4D_SSIM_RADIUS; k <= S4D_SSIM_RADIUS; ++k) t[static_cast<size_t>(k + S4D_SSIM_RADIUS)] = T(w[std::abs(k)]);
  return t;
}

// Separable zero-padded filtering of `planes` maps of an interleaved [H, W, C] image.
template <class T>
std::vector<T> ssim_filter(const std::vector<T>& in, size_t planes, int width, int height, int channels) {
  const auto taps = ssim_taps<T>();
  const size_t n = static_cast<size_t>(width) * static_cast<size_t>(height) * static_cast<size_t>(channels);
  std::vector<T> h(planes * n, T(0)), v(planes * n, T(0));
  auto index = [&](int x, int y, int c) { return (static_cast<size_t>(y) * width + x) * channels + c; };
  for (size_t m = 0; m < planes; ++m)
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x)
        for (int c = 0; c < channels; ++c) {
          T acc = 0;
          for (int k = -S4D_SSIM_RADIUS; k <= S4D_SSIM_RADIUS; ++k)
            if (x + k >= 0 && x + k < width) acc += taps[static_cast<size_t>(k + S4D_SSIM_RADIUS)] * in[m * n + index(x + k, y, c)];
          h[m * n + index(x, y, c)] = acc;
        }
  for (size_t m = 0; m < planes; ++m)
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x)
        for (int c = 0; c < channels; ++c) {
          T acc = 0;
          for (int k = -S4D_SSIM_RADIUS; k <= S4D_SSIM_RADIUS; ++k)
            if (y + k >= 0 && y + k < height) acc += taps[static_cast<size_t>(k + S4D_SSIM_RADIUS)] * h[m * n + index(x, y + k, c)];
          v[m * n + index(x, y, c)] = acc;
        }
  return v;
}

}  // namespace detail

template <class T>
LossValue<T> l1_ssim_loss(const std::vector<T>& x, const std::vector<T>& y, int width, int height, int channels,
                          T ssim_weight) {
  const size_t n = x.size();
  std::vector<T> stats(5 * n);
  for (size_t e = 0; e < n; ++e) {
    stats[e] = x[e], stats[n + e] = y[e], stats[2 * n + e] = x[e] * x[e];
    stats[3 * n + e] = y[e] * y[e], stats[4 * n + e] = x[e] * y[e];
  }
  const std::vector<T> f = detail::ssim_filter(stats, 5, width, height, channels);
  const T c1 = T(S4D_SSIM_C1), c2 = T(S4D_SSIM_C2), scale = -ssim_weight / static_cast<T>(n);
  std::vector<T> dmaps(3 * n);
  LossValue<T> out;
  for (size_t e = 0; e < n; ++e) {
    const T mx = f[e], my = f[n + e];
    const T a1 = 2 * mx * my + c1, a2 = 2 * (f[4 * n + e] - mx * my) + c2;
    const T b1 = mx * mx + my * my + c1, b2 = (f[2 * n + e] - mx * mx) + (f[3 * n + e] - my * my) + c2;
    const T s = a1 * a2 / (b1 * b2);
    out.ssim += s;
    out.l1 += std::abs(x[e] - y[e]);
    dmaps[e] = scale * s * (2 * my / a1 - 2 * my / a2 - 2 * mx / b1 + 2 * mx / b2);
    dmaps[n + e] = scale * s * (-1 / b2);
    dmaps[2 * n + e] = scale * s * (2 / a2);
  }
  out.ssim /= static_cast<T>(n), out.l1 /= static_cast<T>(n);
  out.loss = (1 - ssim_weight) * out.l1 + ssim_weight * (1 - out.ssim);
  // The zero-padded symmetric window is its own adjoint: filter the dS maps the same way.
  const std::vector<T> g = detail::ssim_filter(dmaps, 3, width, height, channels);
  out.grad.resize(n);
  for (size_t e = 0; e < n; ++e) {
    const T d = x[e] - y[e];
    const T sign = d > 0 ? T(1) : (d < 0 ? T(-1) : T(0));
    out.grad[e] = g[e] + 2 * x[e] * g[n + e] + y[e] * g[2 * n + e] + (1 - ssim_weight) / static_cast<T>(n) * sign;
  }
  return out;
}

}  // namespace s4d::ref
