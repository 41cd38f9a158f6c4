// CPU twins of the network layers' backward kernels (shaders/nn/*_bwd.comp, nn_conv_wgrad,
// nn_channel_dots, nn_mse; layouts in shaders/shared/s4d_nn_grad.h): the adjoints of the forward
// twins in nn_ref.h, written as loops over the forward's reads so they are right by construction at
// reflected borders and pooling ties. Templated on the scalar type; tests check them against finite
// differences of the forward twins in double and the float kernels against them.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "s4d/ref/nn_ref.h"

namespace s4d::ref {

// dL/dx of ReflectionPad2d(1) + Conv2d(cin, cout, 3) (no ReLU: see relu_bwd), dy [cout, h, w].
template <class T>
Chw<T> conv3x3_bwd_input(const Chw<T>& dy, const std::vector<T>& weight, uint32_t cin) {
  Chw<T> dx(cin, dy.h, dy.w);
  for (uint32_t o = 0; o < dy.c; ++o)
    for (uint32_t py = 0; py < dy.h; ++py)
      for (uint32_t px = 0; px < dy.w; ++px)
        for (uint32_t i = 0; i < cin; ++i)
          for (int ky = 0; ky < 3; ++ky)
            for (int kx = 0; kx < 3; ++kx)
              dx.at(i, reflect1(int64_t{py} + ky - 1, dy.h), reflect1(int64_t{px} + kx - 1, dy.w)) +=
                  weight[((size_t{o} * cin + i) * 3 + ky) * 3 + kx] * dy.at(o, py, px);
  return dx;
}

// dL/dx of Conv2d(cin, cout, 1): W^T dy.
template <class T>
Chw<T> conv1x1_bwd_input(const Chw<T>& dy, const std::vector<T>& weight, uint32_t cin) {
  Chw<T> dx(cin, dy.h, dy.w);
  const size_t n = size_t{dy.h} * dy.w;
  for (uint32_t o = 0; o < dy.c; ++o)
    for (uint32_t i = 0; i < cin; ++i)
      for (size_t p = 0; p < n; ++p) dx.v[i * n + p] += weight[size_t{o} * cin + i] * dy.v[o * n + p];
  return dx;
}

template <class T>
struct ConvGradsRef {
  std::vector<T> weight, bias;  // [cout, cin, k, k], [cout]
};

// dL/dW and dL/db of Conv2d(k = 1) or, k = 3, of ReflectionPad2d(1) + Conv2d(k = 3), x the layer's input.
template <class T>
ConvGradsRef<T> conv_wgrad(const Chw<T>& x, const Chw<T>& dy, uint32_t k) {
  ConvGradsRef<T> g{std::vector<T>(size_t{dy.c} * x.c * k * k, T(0)), std::vector<T>(dy.c, T(0))};
  const int half = static_cast<int>(k / 2);
  for (uint32_t o = 0; o < dy.c; ++o)
    for (uint32_t py = 0; py < dy.h; ++py)
      for (uint32_t px = 0; px < dy.w; ++px) {
        const T d = dy.at(o, py, px);
        g.bias[o] += d;
        for (uint32_t i = 0; i < x.c; ++i)
          for (uint32_t ky = 0; ky < k; ++ky)
            for (uint32_t kx = 0; kx < k; ++kx)
              g.weight[((size_t{o} * x.c + i) * k + ky) * k + kx] +=
                  d * x.at(i, reflect1(int64_t{py} + ky - half, x.h), reflect1(int64_t{px} + kx - half, x.w));
      }
  return g;
}

// dL/d(input) of ReLU from its output y: dy where y > 0, else 0.
template <class T>
Chw<T> relu_bwd(Chw<T> dy, const Chw<T>& y) {
  for (size_t i = 0; i < dy.v.size(); ++i)
    if (!(y.v[i] > T(0))) dy.v[i] = T(0);
  return dy;
}

// Adjoint of upsample2: each input value collects its 2x2 block.
template <class T>
Chw<T> upsample2_bwd(const Chw<T>& dy) {
  Chw<T> dx(dy.c, dy.h / 2, dy.w / 2);
  for (uint32_t c = 0; c < dy.c; ++c)
    for (uint32_t py = 0; py < dy.h; ++py)
      for (uint32_t px = 0; px < dy.w; ++px) dx.at(c, py / 2, px / 2) += dy.at(c, py, px);
  return dx;
}

// Adjoint of maxpool2_ceil: each window's dy goes to its first maximum in row-major order.
template <class T>
Chw<T> maxpool2_ceil_bwd(const Chw<T>& x, const Chw<T>& dy) {
  Chw<T> dx(x.c, x.h, x.w);
  for (uint32_t c = 0; c < x.c; ++c)
    for (uint32_t oy = 0; oy < dy.h; ++oy)
      for (uint32_t ox = 0; ox < dy.w; ++ox) {
        uint32_t by = 2 * oy, bx = 2 * ox;
        for (uint32_t yy = 2 * oy; yy < std::min(2 * oy + 2, x.h); ++yy)
          for (uint32_t xx = 2 * ox; xx < std::min(2 * ox + 2, x.w); ++xx)
            if (x.at(c, yy, xx) > x.at(c, by, bx)) by = yy, bx = xx;
        dx.at(c, by, bx) += dy.at(c, oy, ox);
      }
  return dx;
}

// Per channel (sum_p a, sum_p a b): [2, c].
template <class T>
std::vector<T> channel_dots(const Chw<T>& a, const Chw<T>& b) {
  const size_t n = size_t{a.h} * a.w;
  std::vector<T> s(2 * size_t{a.c}, T(0));
  for (uint32_t c = 0; c < a.c; ++c)
    for (size_t p = 0; p < n; ++p) {
      s[c] += a.v[c * n + p];
      s[a.c + c] += a.v[c * n + p] * b.v[c * n + p];
    }
  return s;
}

// dL/dx of mean_std (stats = its output, dstats = [dmu..., dsigma...]).
template <class T>
Chw<T> mean_std_bwd(const Chw<T>& x, const std::vector<T>& stats, const std::vector<T>& dstats) {
  const size_t n = size_t{x.h} * x.w;
  Chw<T> dx(x.c, x.h, x.w);
  for (uint32_t c = 0; c < x.c; ++c)
    for (size_t p = 0; p < n; ++p)
      dx.v[c * n + p] = dstats[c] / T(n) +
                        dstats[x.c + c] * (x.v[c * n + p] - stats[c]) / (T(n - 1) * stats[x.c + c]);
  return dx;
}

// dL/dx of normalise (y = (x - mu) / sigma, stats of mean_std), given dy.
template <class T>
Chw<T> normalise_bwd(const Chw<T>& x, const std::vector<T>& stats, const Chw<T>& dy) {
  const size_t n = size_t{x.h} * x.w;
  const Chw<T> y = normalise(x, stats);
  const std::vector<T> sums = channel_dots(dy, y);
  std::vector<T> dstats(2 * size_t{x.c});
  for (uint32_t c = 0; c < x.c; ++c) {
    dstats[c] = -sums[c] / stats[x.c + c];
    dstats[x.c + c] = -sums[x.c + c] / stats[x.c + c];
  }
  Chw<T> dx = mean_std_bwd(x, stats, dstats);
  for (uint32_t c = 0; c < x.c; ++c)
    for (size_t p = 0; p < n; ++p) dx.v[c * n + p] += dy.v[c * n + p] / stats[x.c + c];
  return dx;
}

// dL/dx of squares_over_sum, da [c].
template <class T>
Chw<T> squares_over_sum_bwd(const Chw<T>& x, const std::vector<T>& da) {
  const size_t n = size_t{x.h} * x.w;
  const std::vector<T> sums = channel_dots(x, x);
  Chw<T> dx(x.c, x.h, x.w);
  for (uint32_t c = 0; c < x.c; ++c) {
    const T a = sums[x.c + c] / sums[c];
    for (size_t p = 0; p < n; ++p) dx.v[c * n + p] = da[c] * (T(2) * x.v[c * n + p] - a) / sums[c];
  }
  return dx;
}

// sum (a - b)^2.
template <class T>
T squared_error(const std::vector<T>& a, const std::vector<T>& b) {
  T s = 0;
  for (size_t i = 0; i < a.size(); ++i) s += (a[i] - b[i]) * (a[i] - b[i]);
  return s;
}

// AvgPool2d(3, 1): [c, h - 2, w - 2].
template <class T>
Chw<T> avgpool3(const Chw<T>& x) {
  Chw<T> y(x.c, x.h - 2, x.w - 2);
  for (uint32_t c = 0; c < x.c; ++c)
    for (uint32_t py = 0; py < y.h; ++py)
      for (uint32_t px = 0; px < y.w; ++px) {
        T s = 0;
        for (uint32_t dy = 0; dy < 3; ++dy)
          for (uint32_t dx = 0; dx < 3; ++dx) s += x.at(c, py + dy, px + dx);
        y.at(c, py, px) = s / T(9);
      }
  return y;
}

// Adjoint of avgpool3 (dy [c, h - 2, w - 2]).
template <class T>
Chw<T> avgpool3_bwd(const Chw<T>& dy) {
  Chw<T> dx(dy.c, dy.h + 2, dy.w + 2);
  for (uint32_t c = 0; c < dy.c; ++c)
    for (uint32_t py = 0; py < dy.h; ++py)
      for (uint32_t px = 0; px < dy.w; ++px)
        for (uint32_t a = 0; a < 3; ++a)
          for (uint32_t b = 0; b < 3; ++b) dx.at(c, py + a, px + b) += dy.at(c, py, px) / T(9);
  return dx;
}

// HGST's self-similarity of v >= 0 summed over channels: sum_c mean_i min_j (1 - v_i v_j / S), S the
// sum of squares of the whole tensor (written as the minimum over j, not in closed form).
template <class T>
T selfsim(const Chw<T>& v) {
  const size_t n = size_t{v.h} * v.w;
  T s = 0, total = 0;
  for (const T e : v.v) s += e * e;
  for (uint32_t c = 0; c < v.c; ++c) {
    T mean = 0;
    for (size_t i = 0; i < n; ++i) {
      T m = std::numeric_limits<T>::infinity();
      for (size_t j = 0; j < n; ++j) m = std::min(m, T(1) - v.v[c * n + i] * v.v[c * n + j] / s);
      mean += m / T(n);
    }
    total += mean;
  }
  return total;
}

// d selfsim / dv for v >= 0, where min_j (1 - v_i v_j / S) = 1 - v_i max(v) / S.
template <class T>
Chw<T> selfsim_bwd(const Chw<T>& v) {
  const size_t n = size_t{v.h} * v.w;
  T s = 0, t = 0;
  for (const T e : v.v) s += e * e;
  std::vector<T> mean(v.c, T(0)), mx(v.c);
  std::vector<size_t> arg(v.c, 0);
  for (uint32_t c = 0; c < v.c; ++c) {
    mx[c] = v.v[c * n];
    for (size_t i = 0; i < n; ++i) {
      mean[c] += v.v[c * n + i] / T(n);
      if (v.v[c * n + i] > mx[c]) mx[c] = v.v[c * n + i], arg[c] = i;
    }
    t += mean[c] * mx[c];
  }
  Chw<T> g(v.c, v.h, v.w);
  for (uint32_t c = 0; c < v.c; ++c)
    for (size_t i = 0; i < n; ++i)
      g.v[c * n + i] = -mx[c] / (T(n) * s) - (i == arg[c] ? mean[c] / s : T(0)) + T(2) * t * v.v[c * n + i] / (s * s);
  return g;
}

// sum over channels of |x[y, x] - x[y, x + 1]| + |x[y, x] - x[y + 1, x]| (MCCNet's TV term).
template <class T>
T tv_l1(const Chw<T>& x) {
  T s = 0;
  for (uint32_t c = 0; c < x.c; ++c)
    for (uint32_t py = 0; py < x.h; ++py)
      for (uint32_t px = 0; px < x.w; ++px) {
        if (px + 1 < x.w) s += std::abs(x.at(c, py, px) - x.at(c, py, px + 1));
        if (py + 1 < x.h) s += std::abs(x.at(c, py, px) - x.at(c, py + 1, px));
      }
  return s;
}

// d tv_l1 / dx, with sign(0) = 0.
template <class T>
Chw<T> tv_l1_bwd(const Chw<T>& x) {
  auto sign = [](T v) { return T((v > 0) - (v < 0)); };
  Chw<T> g(x.c, x.h, x.w);
  for (uint32_t c = 0; c < x.c; ++c)
    for (uint32_t py = 0; py < x.h; ++py)
      for (uint32_t px = 0; px < x.w; ++px) {
        if (px + 1 < x.w) {
          const T s = sign(x.at(c, py, px) - x.at(c, py, px + 1));
          g.at(c, py, px) += s;
          g.at(c, py, px + 1) -= s;
        }
        if (py + 1 < x.h) {
          const T s = sign(x.at(c, py, px) - x.at(c, py + 1, px));
          g.at(c, py, px) += s;
          g.at(c, py + 1, px) -= s;
        }
      }
  return g;
}

}  // namespace s4d::ref
