// CPU twins of the network layers in shaders/nn (layouts in shaders/shared/s4d_nn.h), written from
// the PyTorch definitions: one image, [C, H, W] row-major, weights [Cout, Cin, k, k]. Templated on
// the scalar type; tests run them in double against the float kernels.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "s4d/util/chw.h"

namespace s4d::ref {

using util::Chw;  // the twins' images: s4d/util/chw.h, shared with the metrics

// ReflectionPad2d(1): -1 -> 1, n -> n - 2.
inline uint32_t reflect1(int64_t i, uint32_t n) {
  return static_cast<uint32_t>(i < 0 ? -i : (i >= n ? 2 * int64_t{n} - 2 - i : i));
}

template <class T>
Chw<T> relu(Chw<T> x) {
  for (T& e : x.v) e = std::max(e, T(0));
  return x;
}

// ReflectionPad2d(1) + Conv2d(cin, cout, 3): weight [cout, cin, 3, 3], bias [cout].
template <class T>
Chw<T> conv3x3(const Chw<T>& x, const std::vector<T>& weight, const std::vector<T>& bias, uint32_t cout,
               bool with_relu) {
  Chw<T> y(cout, x.h, x.w);
  for (uint32_t o = 0; o < cout; ++o)
    for (uint32_t py = 0; py < x.h; ++py)
      for (uint32_t px = 0; px < x.w; ++px) {
        T acc = bias[o];
        for (uint32_t i = 0; i < x.c; ++i)
          for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx)
              acc += weight[((size_t{o} * x.c + i) * 3 + (dy + 1)) * 3 + (dx + 1)] *
                     x.at(i, reflect1(int64_t{py} + dy, x.h), reflect1(int64_t{px} + dx, x.w));
        y.at(o, py, px) = with_relu ? std::max(acc, T(0)) : acc;
      }
  return y;
}

// Conv2d(cin, cout, k, stride, padding) with zero padding: weight [cout, cin, k, k].
template <class T>
Chw<T> conv2d(const Chw<T>& x, const std::vector<T>& weight, const std::vector<T>& bias, uint32_t cout, uint32_t k,
              uint32_t stride, uint32_t pad, bool with_relu) {
  Chw<T> y(cout, (x.h + 2 * pad - k) / stride + 1, (x.w + 2 * pad - k) / stride + 1);
  for (uint32_t o = 0; o < cout; ++o)
    for (uint32_t py = 0; py < y.h; ++py)
      for (uint32_t px = 0; px < y.w; ++px) {
        T acc = bias[o];
        for (uint32_t i = 0; i < x.c; ++i)
          for (uint32_t ky = 0; ky < k; ++ky)
            for (uint32_t kx = 0; kx < k; ++kx) {
              const int64_t sy = int64_t{py} * stride + ky - pad, sx = int64_t{px} * stride + kx - pad;
              if (sy < 0 || sx < 0 || sy >= x.h || sx >= x.w) continue;
              acc += weight[((size_t{o} * x.c + i) * k + ky) * k + kx] *
                     x.at(i, static_cast<uint32_t>(sy), static_cast<uint32_t>(sx));
            }
        y.at(o, py, px) = with_relu ? std::max(acc, T(0)) : acc;
      }
  return y;
}

// Conv2d(cin, cout, 3, padding=1) (zero padding, torchvision's VGG): the twin of nn::conv3x3_zero_pad.
template <class T>
Chw<T> conv3x3_zero_pad(const Chw<T>& x, const std::vector<T>& weight, const std::vector<T>& bias, uint32_t cout,
                        bool with_relu) {
  return conv2d(x, weight, bias, cout, 3, 1, 1, with_relu);
}

// MaxPool2d(3, 2, pad) (floor mode; pad 0 or 1, padded positions never win).
template <class T>
Chw<T> maxpool3s2(const Chw<T>& x, uint32_t pad = 0) {
  Chw<T> y(x.c, (x.h + 2 * pad - 3) / 2 + 1, (x.w + 2 * pad - 3) / 2 + 1);
  for (uint32_t ch = 0; ch < x.c; ++ch)
    for (uint32_t py = 0; py < y.h; ++py)
      for (uint32_t px = 0; px < y.w; ++px) {
        T m = -std::numeric_limits<T>::infinity();
        for (uint32_t dy = 0; dy < 3; ++dy)
          for (uint32_t dx = 0; dx < 3; ++dx) {
            const int64_t sy = int64_t{2 * py + dy} - pad, sx = int64_t{2 * px + dx} - pad;
            if (sy >= 0 && sy < x.h && sx >= 0 && sx < x.w) m = std::max(m, x.at(ch, uint32_t(sy), uint32_t(sx)));
          }
        y.at(ch, py, px) = m;
      }
  return y;
}

// Conv2d(cin, cout, 1), or Linear(cin, cout) on a [cin, 1, 1] tensor: weight [cout, cin].
template <class T>
Chw<T> conv1x1(const Chw<T>& x, const std::vector<T>& weight, const std::vector<T>& bias, uint32_t cout,
               bool with_relu) {
  Chw<T> y(cout, x.h, x.w);
  for (uint32_t o = 0; o < cout; ++o)
    for (uint32_t py = 0; py < x.h; ++py)
      for (uint32_t px = 0; px < x.w; ++px) {
        T acc = bias[o];
        for (uint32_t i = 0; i < x.c; ++i) acc += weight[size_t{o} * x.c + i] * x.at(i, py, px);
        y.at(o, py, px) = with_relu ? std::max(acc, T(0)) : acc;
      }
  return y;
}

// MaxPool2d(2, 2, 0, ceil_mode=True): windows past the last row or column take what they cover.
template <class T>
Chw<T> maxpool2_ceil(const Chw<T>& x) {
  Chw<T> y(x.c, (x.h + 1) / 2, (x.w + 1) / 2);
  for (uint32_t ch = 0; ch < x.c; ++ch)
    for (uint32_t py = 0; py < y.h; ++py)
      for (uint32_t px = 0; px < y.w; ++px) {
        T m = x.at(ch, 2 * py, 2 * px);
        for (uint32_t yy = 2 * py; yy < std::min(2 * py + 2, x.h); ++yy)
          for (uint32_t xx = 2 * px; xx < std::min(2 * px + 2, x.w); ++xx) m = std::max(m, x.at(ch, yy, xx));
        y.at(ch, py, px) = m;
      }
  return y;
}

// MaxPool2d(2, 2) (floor mode): a last odd row or column is dropped.
template <class T>
Chw<T> maxpool2_floor(const Chw<T>& x) {
  Chw<T> y(x.c, x.h / 2, x.w / 2);
  for (uint32_t ch = 0; ch < x.c; ++ch)
    for (uint32_t py = 0; py < y.h; ++py)
      for (uint32_t px = 0; px < y.w; ++px)
        y.at(ch, py, px) = std::max(std::max(x.at(ch, 2 * py, 2 * px), x.at(ch, 2 * py, 2 * px + 1)),
                                    std::max(x.at(ch, 2 * py + 1, 2 * px), x.at(ch, 2 * py + 1, 2 * px + 1)));
  return y;
}

// DISTS's L2pooling: sqrt(sum_{dy,dx} g[dy] g[dx] x^2 + eps) with g = (1, 2, 1) / 4, stride 2,
// zero padding 1: [c, ceil(h/2), ceil(w/2)].
template <class T>
Chw<T> l2pool(const Chw<T>& x, T eps) {
  Chw<T> y(x.c, (x.h + 1) / 2, (x.w + 1) / 2);
  const T g[3] = {T(0.25), T(0.5), T(0.25)};
  for (uint32_t ch = 0; ch < x.c; ++ch)
    for (uint32_t py = 0; py < y.h; ++py)
      for (uint32_t px = 0; px < y.w; ++px) {
        T sum = 0;
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const int64_t sy = 2 * int64_t{py} + dy, sx = 2 * int64_t{px} + dx;
            if (sy < 0 || sx < 0 || sy >= x.h || sx >= x.w) continue;
            const T v = x.at(ch, static_cast<uint32_t>(sy), static_cast<uint32_t>(sx));
            sum += g[dy + 1] * g[dx + 1] * v * v;
          }
        y.at(ch, py, px) = std::sqrt(sum + eps);
      }
  return y;
}

// Upsample(scale_factor=2, mode='nearest').
template <class T>
Chw<T> upsample2(const Chw<T>& x) {
  Chw<T> y(x.c, 2 * x.h, 2 * x.w);
  for (uint32_t ch = 0; ch < x.c; ++ch)
    for (uint32_t py = 0; py < y.h; ++py)
      for (uint32_t px = 0; px < y.w; ++px) y.at(ch, py, px) = x.at(ch, py / 2, px / 2);
  return y;
}

// AvgPool2d(2) (floor mode): the mean of each 2x2 window, a last odd row or column dropped.
template <class T>
Chw<T> avgpool2(const Chw<T>& x) {
  Chw<T> y(x.c, x.h / 2, x.w / 2);
  for (uint32_t ch = 0; ch < x.c; ++ch)
    for (uint32_t py = 0; py < y.h; ++py)
      for (uint32_t px = 0; px < y.w; ++px)
        y.at(ch, py, px) = (x.at(ch, 2 * py, 2 * px) + x.at(ch, 2 * py, 2 * px + 1) + x.at(ch, 2 * py + 1, 2 * px) +
                            x.at(ch, 2 * py + 1, 2 * px + 1)) /
                           T(4);
  return y;
}

// x[c, 2 y, 2 x]: [c, ceil(h / 2), ceil(w / 2)] (a 1x1 stride-2 convolution's sampling).
template <class T>
Chw<T> subsample2(const Chw<T>& x) {
  Chw<T> y(x.c, (x.h + 1) / 2, (x.w + 1) / 2);
  for (uint32_t ch = 0; ch < x.c; ++ch)
    for (uint32_t py = 0; py < y.h; ++py)
      for (uint32_t px = 0; px < y.w; ++px) y.at(ch, py, px) = x.at(ch, 2 * py, 2 * px);
  return y;
}

// AdaIN's calc_mean_std: [2, c] = per-channel means, then sqrt(unbiased variance + eps).
template <class T>
std::vector<T> mean_std(const Chw<T>& x, T eps) {
  const size_t n = size_t{x.h} * x.w;
  std::vector<T> stats(2 * size_t{x.c});
  for (uint32_t ch = 0; ch < x.c; ++ch) {
    const T* v = x.v.data() + ch * n;
    T sum = 0, centred = 0;
    for (size_t i = 0; i < n; ++i) sum += v[i];
    const T mean = sum / T(n);
    for (size_t i = 0; i < n; ++i) centred += (v[i] - mean) * (v[i] - mean);
    stats[ch] = mean;
    stats[x.c + ch] = std::sqrt(centred / T(n - 1) + eps);
  }
  return stats;
}

// MCC's style weights per channel: sum(x^2) / sum(x) over the pixels (ALGORITHMS.md 4.2).
template <class T>
std::vector<T> squares_over_sum(const Chw<T>& x) {
  const size_t n = size_t{x.h} * x.w;
  std::vector<T> a(x.c);
  for (uint32_t ch = 0; ch < x.c; ++ch) {
    T sum = 0, squares = 0;
    for (size_t i = 0; i < n; ++i) {
      sum += x.v[ch * n + i];
      squares += x.v[ch * n + i] * x.v[ch * n + i];
    }
    a[ch] = squares / sum;
  }
  return a;
}

// AdaIN blended with the content: alpha (sigma_s (x - mu_c) / sigma_c + mu_s) + (1 - alpha) x.
template <class T>
Chw<T> adain(Chw<T> x, const std::vector<T>& content_stats, const std::vector<T>& style_stats, T alpha) {
  const size_t n = size_t{x.h} * x.w;
  for (uint32_t ch = 0; ch < x.c; ++ch)
    for (size_t i = 0; i < n; ++i) {
      T& v = x.v[ch * n + i];
      const T styled = (v - content_stats[ch]) / content_stats[x.c + ch] * style_stats[x.c + ch] + style_stats[ch];
      v = alpha * styled + (T(1) - alpha) * v;
    }
  return x;
}

// MCC's normal(): (x - mu) / sigma with the stats of mean_std.
template <class T>
Chw<T> normalise(Chw<T> x, const std::vector<T>& stats) {
  const size_t n = size_t{x.h} * x.w;
  for (uint32_t ch = 0; ch < x.c; ++ch)
    for (size_t i = 0; i < n; ++i) x.v[ch * n + i] = (x.v[ch * n + i] - stats[ch]) / stats[x.c + ch];
  return x;
}

// x[c, :] *= s[c].
template <class T>
Chw<T> scale_channels(Chw<T> x, const std::vector<T>& s) {
  const size_t n = size_t{x.h} * x.w;
  for (uint32_t ch = 0; ch < x.c; ++ch)
    for (size_t i = 0; i < n; ++i) x.v[ch * n + i] *= s[ch];
  return x;
}

// interpolate(x, size=(out_h, out_w)) in nearest mode: source floor(dst * in / out).
template <class T>
Chw<T> resize_nearest(const Chw<T>& x, uint32_t out_h, uint32_t out_w) {
  Chw<T> y(x.c, out_h, out_w);
  for (uint32_t ch = 0; ch < x.c; ++ch)
    for (uint32_t py = 0; py < out_h; ++py)
      for (uint32_t px = 0; px < out_w; ++px)
        y.at(ch, py, px) = x.at(ch, static_cast<uint32_t>(uint64_t{py} * x.h / out_h),
                                static_cast<uint32_t>(uint64_t{px} * x.w / out_w));
  return y;
}

// torch.cat(parts, dim=1) of tensors of one size.
template <class T>
Chw<T> concat_channels(const std::vector<Chw<T>>& parts) {
  Chw<T> y(0, parts.at(0).h, parts.at(0).w);
  for (const Chw<T>& t : parts) {
    y.v.insert(y.v.end(), t.v.begin(), t.v.end());
    y.c += t.c;
  }
  return y;
}

// AdaAttN's logits [n_c, n_s] (row-major): S[i, j] = sum_k q[k, i] k[k, j].
template <class T>
std::vector<T> attention_scores(const Chw<T>& q, const Chw<T>& k) {
  const size_t n_c = size_t{q.h} * q.w, n_s = size_t{k.h} * k.w;
  std::vector<T> s(n_c * n_s, T(0));
  for (uint32_t c = 0; c < q.c; ++c)
    for (size_t i = 0; i < n_c; ++i)
      for (size_t j = 0; j < n_s; ++j) s[i * n_s + j] += q.v[c * n_c + i] * k.v[c * n_s + j];
  return s;
}

// Softmax(dim=-1) of each row of a [rows, n] matrix, the row maximum subtracted first.
template <class T>
std::vector<T> softmax_rows(std::vector<T> s, size_t n) {
  for (size_t r = 0; r * n < s.size(); ++r) {
    T* row = s.data() + r * n;
    const T m = *std::max_element(row, row + n);
    T sum = 0;
    for (size_t j = 0; j < n; ++j) sum += row[j] = std::exp(row[j] - m);
    for (size_t j = 0; j < n; ++j) row[j] /= sum;
  }
  return s;
}

// out[c, i] = sqrt(relu(sum_j P[i, j] V[c, j]^2 - M^2)) content[c, i] + M, M = sum_j P[i, j] V[c, j].
template <class T>
Chw<T> attention_apply(const std::vector<T>& p, const Chw<T>& v, const Chw<T>& content) {
  const size_t n_c = size_t{content.h} * content.w, n_s = size_t{v.h} * v.w;
  Chw<T> y(content.c, content.h, content.w);
  for (uint32_t c = 0; c < v.c; ++c)
    for (size_t i = 0; i < n_c; ++i) {
      T mean = 0, squares = 0;
      for (size_t j = 0; j < n_s; ++j) {
        const T val = v.v[c * n_s + j];
        mean += p[i * n_s + j] * val;
        squares += p[i * n_s + j] * val * val;
      }
      y.v[c * n_c + i] = std::sqrt(std::max(squares - mean * mean, T(0))) * content.v[c * n_c + i] + mean;
    }
  return y;
}

// A transformer's attention output out[c, i] = sum_j P[i, j] V[c, j] ([c] x the rows of p).
template <class T>
Chw<T> attention_average(const std::vector<T>& p, const Chw<T>& v) {
  const size_t n_s = size_t{v.h} * v.w, rows = p.size() / n_s;
  Chw<T> y(v.c, 1, static_cast<uint32_t>(rows));
  for (uint32_t c = 0; c < v.c; ++c)
    for (size_t i = 0; i < rows; ++i)
      for (size_t j = 0; j < n_s; ++j) y.v[c * rows + i] += p[i * n_s + j] * v.v[c * n_s + j];
  return y;
}

// LayerNorm(C, eps) of every pixel (token) over the channels: biased variance, then weight, bias.
template <class T>
Chw<T> layernorm(Chw<T> x, const std::vector<T>& weight, const std::vector<T>& bias, T eps) {
  const size_t n = size_t{x.h} * x.w;
  for (size_t t = 0; t < n; ++t) {
    const T shift = x.v[t];  // as the kernel: sums of x - x[0], so a large offset cannot swamp the spread
    T sum = 0, centred = 0;
    for (uint32_t ch = 0; ch < x.c; ++ch) sum += x.v[ch * n + t] - shift;
    const T mean = sum / T(x.c);  // of x - shift
    for (uint32_t ch = 0; ch < x.c; ++ch)
      centred += (x.v[ch * n + t] - shift - mean) * (x.v[ch * n + t] - shift - mean);
    const T inv = T(1) / std::sqrt(centred / T(x.c) + eps);
    for (uint32_t ch = 0; ch < x.c; ++ch)
      x.v[ch * n + t] = (x.v[ch * n + t] - shift - mean) * inv * weight[ch] + bias[ch];
  }
  return x;
}

// GELU(approximate='none'): x Phi(x) = x (1 + erf(x / sqrt 2)) / 2, as x erfc(-x / sqrt 2) / 2 so
// that large negative x keep their tiny values.
template <class T>
Chw<T> gelu(Chw<T> x) {
  for (T& e : x.v) e = e * std::erfc(-e / std::sqrt(T(2))) / T(2);
  return x;
}

// A vision transformer's tokens [c, 1, 1 + gh gw]: column 0 pos[:, 0] (the class token and its
// position embedding), column t the patch embedding t - 1 (row-major over [gh, gw]) plus pos[:, t].
// pos [c, 1, 1]: only the first token, no position embedding (CLIP's attention pooling).
template <class T>
Chw<T> vit_embed(const Chw<T>& patches, const Chw<T>& pos) {
  const size_t n = size_t{patches.h} * patches.w + 1;
  Chw<T> y(patches.c, 1, static_cast<uint32_t>(n));
  for (uint32_t ch = 0; ch < patches.c; ++ch)
    for (size_t t = 0; t < n; ++t)
      y.v[ch * n + t] = (pos.w == 1 ? (t == 0 ? pos.v[ch] : T(0)) : pos.v[ch * n + t]) +
                        (t == 0 ? T(0) : patches.v[ch * (n - 1) + t - 1]);
  return y;
}

// The whole attention: softmax(Q^T K) weighted statistics of V applied to the content.
template <class T>
Chw<T> attention(const Chw<T>& q, const Chw<T>& k, const Chw<T>& v, const Chw<T>& content) {
  return attention_apply(softmax_rows(attention_scores(q, k), size_t{k.h} * k.w), v, content);
}

// a + b.
template <class T>
Chw<T> add(Chw<T> a, const Chw<T>& b) {
  for (size_t i = 0; i < a.v.size(); ++i) a.v[i] += b.v[i];
  return a;
}

// GroupNorm(groups, C, eps) (+ ReLU) of each cell of cell_h rows (a batch of images stacked along H)
// over the window rows [row0, row0 + rows) x cols [col0, col0 + cols) of the cell (biased variance,
// then weight, bias); every value outside the windows becomes 0 (nn_group_norm).
template <class T>
Chw<T> group_norm_cells(const Chw<T>& x, const std::vector<T>& weight, const std::vector<T>& bias, uint32_t groups, T eps,
                        uint32_t cell_h, uint32_t row0, uint32_t rows, uint32_t col0, uint32_t cols, bool with_relu) {
  Chw<T> y(x.c, x.h, x.w);
  const uint32_t per_group = x.c / groups;
  for (uint32_t cell = 0; cell < x.h / cell_h; ++cell)
    for (uint32_t g = 0; g < groups; ++g) {
      const auto window = [&](auto&& f) {
        for (uint32_t ch = g * per_group; ch < (g + 1) * per_group; ++ch)
          for (uint32_t r = 0; r < rows; ++r)
            for (uint32_t c = 0; c < cols; ++c) f(ch, cell * cell_h + row0 + r, col0 + c);
      };
      const T n = T(per_group) * T(rows) * T(cols);
      T sum = 0, centred = 0;
      window([&](uint32_t ch, uint32_t py, uint32_t px) { sum += x.at(ch, py, px); });
      const T mean = sum / n;
      window([&](uint32_t ch, uint32_t py, uint32_t px) { centred += (x.at(ch, py, px) - mean) * (x.at(ch, py, px) - mean); });
      const T inv = T(1) / std::sqrt(centred / n + eps);
      window([&](uint32_t ch, uint32_t py, uint32_t px) {
        const T v = (x.at(ch, py, px) - mean) * inv * weight[ch] + bias[ch];
        y.at(ch, py, px) = with_relu ? std::max(v, T(0)) : v;
      });
    }
  return y;
}

// F.unfold(x, k, padding=pad, stride): [c k k, out_h, out_w], row (ci k + ky) k + kx holding
// x[ci, oy stride - pad + ky, ox stride - pad + kx], 0 in the padding (nn_im2col).
template <class T>
Chw<T> im2col(const Chw<T>& x, uint32_t k, uint32_t stride, uint32_t pad) {
  Chw<T> y(x.c * k * k, (x.h + 2 * pad - k) / stride + 1, (x.w + 2 * pad - k) / stride + 1);
  for (uint32_t ci = 0; ci < x.c; ++ci)
    for (uint32_t ky = 0; ky < k; ++ky)
      for (uint32_t kx = 0; kx < k; ++kx)
        for (uint32_t oy = 0; oy < y.h; ++oy)
          for (uint32_t ox = 0; ox < y.w; ++ox) {
            const int64_t sy = int64_t{oy} * stride + ky - pad, sx = int64_t{ox} * stride + kx - pad;
            if (sy >= 0 && sy < x.h && sx >= 0 && sx < x.w) y.at((ci * k + ky) * k + kx, oy, ox) = x.at(ci, uint32_t(sy), uint32_t(sx));
          }
  return y;
}

// out[c, r] = in[r, c] of a [rows, cols] matrix (nn_transpose).
template <class T>
std::vector<T> transpose(const std::vector<T>& x, size_t rows, size_t cols) {
  std::vector<T> y(x.size());
  for (size_t r = 0; r < rows; ++r)
    for (size_t c = 0; c < cols; ++c) y[c * rows + r] = x[r * cols + c];
  return y;
}

}  // namespace s4d::ref
