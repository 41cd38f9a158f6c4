// UIQM variant B: xueleichen PSNR-SSIM-UCIQE-UIQM-Python nevaluate.py with scikit-image < 0.18
// (uiqm.h lists the conventions).
#include <algorithm>
#include <cmath>

#include "s4d/metrics/uiqm.h"

namespace s4d::metrics::detail {

namespace {

constexpr double kPlip = 1026.0;  // PLIP gamma = k (Panetta's parameters)

struct Trimmed {
  double mean = 0, var = 0;
};

Trimmed trimmed_stats(std::vector<double> x) {
  std::sort(x.begin(), x.end());
  const size_t t = size_t(0.1 * double(x.size()));
  double s = 0;
  for (size_t i = t; i < x.size() - t; ++i) s += x[i];
  const double n = double(x.size() - 2 * t), mean = s / n;
  double v = 0;
  for (size_t i = t; i < x.size() - t; ++i) v += (x[i] - mean) * (x[i] - mean);
  return {mean, v / n};
}

double uicm(const LevelPlanes& p) {
  const size_t n = p.c[0].size();
  std::vector<double> rg(n), yb(n);
  for (size_t i = 0; i < n; ++i) {
    const int r = int(p.c[0][i]), g = int(p.c[1][i]), b = int(p.c[2][i]);
    rg[i] = double((r - g + 256) % 256);   // uint8 subtraction wraps
    yb[i] = double((r + g) % 256) / 2 - b;  // uint8 addition wraps, then true division
  }
  const Trimmed a = trimmed_stats(rg), y = trimmed_stats(yb);
  return -0.0268 * std::sqrt(a.mean * a.mean + y.mean * y.mean) + 0.1586 * std::sqrt(a.var + y.var);
}

// scikit-image 0.17 filters.sobel on level / 255: kernels [1 2 1]^T [1 0 -1] / 4, magnitude
// sqrt(h^2 + v^2) / sqrt(2), the border rows and columns set to 0.
std::vector<double> sobel_skimage(const std::vector<double>& levels, int w, int h) {
  std::vector<double> mag(levels.size(), 0.0);
  auto f = [&](int x, int y) { return levels[size_t(y) * w + x] / 255.0; };
  for (int y = 1; y + 1 < h; ++y)
    for (int x = 1; x + 1 < w; ++x) {
      const double gh = ((f(x - 1, y - 1) + 2 * f(x, y - 1) + f(x + 1, y - 1)) -
                         (f(x - 1, y + 1) + 2 * f(x, y + 1) + f(x + 1, y + 1))) / 4;
      const double gv = ((f(x - 1, y - 1) + 2 * f(x - 1, y) + f(x - 1, y + 1)) -
                         (f(x + 1, y - 1) + 2 * f(x + 1, y) + f(x + 1, y + 1))) / 4;
      mag[size_t(y) * w + x] = std::sqrt(gh * gh + gv * gv) / std::sqrt(2.0);
    }
  return mag;
}

// Calls fn(x0, x1, y0, y1) for each 8x8 block, the last row and column of blocks taking the
// remainder; returns the block count.
template <class Fn>
double for_blocks8(int w, int h, Fn fn) {
  const int nx = (h + 7) / 8, ny = (w + 7) / 8;  // the script's num_x runs over rows
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < ny; ++j) fn(j * 8, j < ny - 1 ? (j + 1) * 8 : w, i * 8, i < nx - 1 ? (i + 1) * 8 : h);
  return double(nx) * double(ny);
}

void block_range(const std::vector<double>& v, int w, int x0, int x1, int y0, int y1, double& lo, double& hi) {
  lo = hi = v[size_t(y0) * w + x0];
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) lo = std::min(lo, v[size_t(y) * w + x]), hi = std::max(hi, v[size_t(y) * w + x]);
}

double eme8(const std::vector<double>& e, int w, int h) {
  double sum = 0;
  const double blocks = for_blocks8(w, h, [&](int x0, int x1, int y0, int y1) {
    double lo = 0, hi = 0;
    block_range(e, w, x0, x1, y0, y1, lo, hi);
    sum += std::log((hi == 0 ? 1 : hi) / (lo == 0 ? 1 : lo));
  });
  return 2.0 / blocks * sum;
}

double uism(const LevelPlanes& p) {
  const double lambda[3] = {0.299, 0.587, 0.114};
  double s = 0;
  for (int c = 0; c < 3; ++c) {
    std::vector<double> e = sobel_skimage(p.c[c], p.width, p.height);
    for (size_t i = 0; i < e.size(); ++i) e[i] = std::nearbyint(p.c[c][i] * e[i]);  // default mode: half to even, as numpy
    s += lambda[c] * eme8(e, p.width, p.height);
  }
  return s;
}

double uiconm(const LevelPlanes& p) {
  std::vector<double> gray(p.c[0].size());
  for (size_t i = 0; i < gray.size(); ++i)
    gray[i] = p.c[0][i] / 255.0 * 0.2125 + p.c[1][i] / 255.0 * 0.7154 + p.c[2][i] / 255.0 * 0.0721;
  double s = 0;
  const double blocks = for_blocks8(p.width, p.height, [&](int x0, int x1, int y0, int y1) {
    double lo = 0, hi = 0;
    block_range(gray, p.width, x0, x1, y0, y1, lo, hi);
    const double top = kPlip * (hi - lo) / (kPlip - lo);  // PLIP subtraction
    const double bottom = hi + lo - hi * lo / kPlip;      // PLIP addition
    if (bottom == 0) return;                               // all-black block: 0/0 in the script
    const double m = top / bottom;
    if (m != 0) s += m * std::log(m);
  });
  return kPlip - kPlip * std::pow(1 - s / kPlip, 1.0 / blocks);  // PLIP scalar multiplication
}

}  // namespace

UiqmParts uiqm_xueleichen(const LevelPlanes& p) { return {uicm(p), uism(p), uiconm(p)}; }

}  // namespace s4d::metrics::detail
