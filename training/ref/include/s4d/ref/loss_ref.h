// CPU twin of the image loss kernels (shaders/loss): (1 - lambda) L1 + lambda (1 - SSIM) with an
// 11x11 Gaussian window (sigma 1.5), zero padding, per channel, the SSIM map averaged; value and
// gradient with respect to the rendered image. One function per kernel (ssim_hpass, ssim_vpass,
// loss_grad) so each kernel is tested on its own, and l1_ssim_loss chains them. Templated on the
// scalar type.
#pragma once
#include <array>
#include <cmath>
#include <cstddef>
#include <utility>
#include <vector>

#include "s4d_loss.h"

namespace s4d::ref {

struct LossShape {
  int width = 0, height = 0, channels = 0;
  size_t n() const { return static_cast<size_t>(width) * static_cast<size_t>(height) * static_cast<size_t>(channels); }
};

template <class T>
struct LossValue {
  T loss{}, l1{}, ssim{};  // l1 and ssim are means over all elements
  std::vector<T> grad;     // dL/d image, [H*W*C]
};

namespace detail {

// Zero-padded 1-D window along x (step = channels) or y (step = row) over `planes` maps of n.
template <class T>
std::vector<T> ssim_window_pass(const std::vector<T>& in, size_t planes, const LossShape& s, bool along_y) {
  const double w[6] = {S4D_SSIM_W0, S4D_SSIM_W1, S4D_SSIM_W2, S4D_SSIM_W3, S4D_SSIM_W4, S4D_SSIM_W5};
  const size_t n = s.n();
  std::vector<T> out(planes * n, T(0));
  const long step = along_y ? static_cast<long>(s.width) * s.channels : s.channels;
  const int extent = along_y ? s.height : s.width;
  for (size_t m = 0; m < planes; ++m)
    for (size_t e = 0; e < n; ++e) {
      const size_t pixel = e / static_cast<size_t>(s.channels);
      const int coord = static_cast<int>(along_y ? pixel / static_cast<size_t>(s.width) : pixel % static_cast<size_t>(s.width));
      T acc = 0;
      for (int k = -S4D_SSIM_RADIUS; k <= S4D_SSIM_RADIUS; ++k)
        if (coord + k >= 0 && coord + k < extent)
          acc += T(w[std::abs(k)]) * in[m * n + static_cast<size_t>(static_cast<long>(e) + k * step)];
      out[m * n + e] = acc;
    }
  return out;
}

}  // namespace detail

// ssim_hpass, forward mode: the five statistics x, y, x^2, y^2, xy filtered along x, [5n].
template <class T>
std::vector<T> ssim_hpass_stats(const std::vector<T>& x, const std::vector<T>& y, const LossShape& s) {
  const size_t n = s.n();
  std::vector<T> stats(5 * n);
  for (size_t e = 0; e < n; ++e) {
    stats[e] = x[e], stats[n + e] = y[e], stats[2 * n + e] = x[e] * x[e];
    stats[3 * n + e] = y[e] * y[e], stats[4 * n + e] = x[e] * y[e];
  }
  return detail::ssim_window_pass(stats, 5, s, false);
}

// ssim_hpass, backward mode: the three dS maps filtered along x (the symmetric zero-padded window
// is its own adjoint), [3n].
template <class T>
std::vector<T> ssim_hpass_dmaps(const std::vector<T>& dmaps, const LossShape& s) {
  return detail::ssim_window_pass(dmaps, 3, s, false);
}

template <class T>
struct SsimVpass {
  std::vector<T> dmaps;        // [3n] dS/d mu_x, dS/d E[x^2], dS/d E[xy], scaled by -lambda / n
  T ssim_sum{}, l1_sum{};      // what the kernel's partial sums add up to
};

// ssim_vpass: the statistics filtered along y, the SSIM map, its derivative maps and the sums.
template <class T>
SsimVpass<T> ssim_vpass(const std::vector<T>& x, const std::vector<T>& y, const std::vector<T>& stats_h,
                        const LossShape& s, T ssim_weight) {
  const size_t n = s.n();
  const std::vector<T> f = detail::ssim_window_pass(stats_h, 5, s, true);
  const T c1 = T(S4D_SSIM_C1), c2 = T(S4D_SSIM_C2), scale = -ssim_weight / static_cast<T>(n);
  SsimVpass<T> out;
  out.dmaps.resize(3 * n);
  for (size_t e = 0; e < n; ++e) {
    const T mx = f[e], my = f[n + e];
    const T a1 = 2 * mx * my + c1, a2 = 2 * (f[4 * n + e] - mx * my) + c2;
    const T b1 = mx * mx + my * my + c1, b2 = (f[2 * n + e] - mx * mx) + (f[3 * n + e] - my * my) + c2;
    const T ssim = a1 * a2 / (b1 * b2);
    out.ssim_sum += ssim;
    out.l1_sum += std::abs(x[e] - y[e]);
    out.dmaps[e] = scale * ssim * (2 * my / a1 - 2 * my / a2 - 2 * mx / b1 + 2 * mx / b2);
    out.dmaps[n + e] = scale * ssim * (-1 / b2);
    out.dmaps[2 * n + e] = scale * ssim * (2 / a2);
  }
  return out;
}

// loss_grad: the filtered dS maps along y combined with the L1 term into dL/dx, [n].
template <class T>
std::vector<T> loss_grad(const std::vector<T>& x, const std::vector<T>& y, const std::vector<T>& dmaps_h,
                         const LossShape& s, T ssim_weight) {
  const size_t n = s.n();
  const std::vector<T> g = detail::ssim_window_pass(dmaps_h, 3, s, true);
  std::vector<T> grad(n);
  for (size_t e = 0; e < n; ++e) {
    const T d = x[e] - y[e];
    const T sign = d > 0 ? T(1) : (d < 0 ? T(-1) : T(0));  // 0 at 0, like torch.abs
    grad[e] = g[e] + 2 * x[e] * g[n + e] + y[e] * g[2 * n + e] + (1 - ssim_weight) / static_cast<T>(n) * sign;
  }
  return grad;
}

// The whole loss, chaining the kernels' twins.
template <class T>
LossValue<T> l1_ssim_loss(const std::vector<T>& x, const std::vector<T>& y, int width, int height, int channels,
                          T ssim_weight) {
  const LossShape s{width, height, channels};
  const SsimVpass<T> v = ssim_vpass(x, y, ssim_hpass_stats(x, y, s), s, ssim_weight);
  LossValue<T> out;
  out.ssim = v.ssim_sum / static_cast<T>(s.n()), out.l1 = v.l1_sum / static_cast<T>(s.n());
  out.loss = (1 - ssim_weight) * out.l1 + ssim_weight * (1 - out.ssim);
  out.grad = loss_grad(x, y, ssim_hpass_dmaps(v.dmaps, s), s, ssim_weight);
  return out;
}

// tv_grad: squared total variation weight * mean over horizontal and vertical neighbour pairs (per
// channel) of (x_a - x_b)^2; value and gradient.
template <class T>
std::pair<T, std::vector<T>> tv_loss(const std::vector<T>& x, const LossShape& s, T weight) {
  const size_t c = static_cast<size_t>(s.channels), row = static_cast<size_t>(s.width) * c;
  const T pairs = static_cast<T>(s.channels) * (static_cast<T>(s.width - 1) * s.height + static_cast<T>(s.width) * (s.height - 1));
  const T scale = weight / pairs;
  T value = 0;
  std::vector<T> grad(s.n(), T(0));
  auto pair = [&](size_t a, size_t b) {
    const T d = x[b] - x[a];
    value += d * d;
    grad[a] -= 2 * scale * d, grad[b] += 2 * scale * d;
  };
  for (size_t y = 0; y < static_cast<size_t>(s.height); ++y)
    for (size_t xx = 0; xx < static_cast<size_t>(s.width); ++xx)
      for (size_t k = 0; k < c; ++k) {
        const size_t e = y * row + xx * c + k;
        if (xx + 1 < static_cast<size_t>(s.width)) pair(e, e + c);
        if (y + 1 < static_cast<size_t>(s.height)) pair(e, e + row);
      }
  return {value * scale, grad};
}

}  // namespace s4d::ref
