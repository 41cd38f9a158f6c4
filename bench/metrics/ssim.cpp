#include "s4d/metrics/ssim.h"

#include <cmath>

#include "s4d/metrics/image_checks.h"

namespace s4d::metrics {

namespace {

// 'same'-size correlation of one [H, W] plane with the separable window, zero outside the image.
std::vector<double> blur(const std::vector<double>& plane, int w, int h, const std::vector<double>& k) {
  const int r = kSsimWindow / 2;
  std::vector<double> rows(plane.size(), 0.0), out(plane.size(), 0.0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      double s = 0;
      for (int i = -r; i <= r; ++i)
        if (x + i >= 0 && x + i < w) s += k[size_t(i + r)] * plane[size_t(y) * w + size_t(x + i)];
      rows[size_t(y) * w + x] = s;
    }
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      double s = 0;
      for (int i = -r; i <= r; ++i)
        if (y + i >= 0 && y + i < h) s += k[size_t(i + r)] * rows[size_t(y + i) * w + x];
      out[size_t(y) * w + x] = s;
    }
  return out;
}

}  // namespace

std::vector<double> ssim_window_1d() {
  std::vector<double> k(kSsimWindow);
  double sum = 0;
  for (int i = 0; i < kSsimWindow; ++i) {
    const double d = i - kSsimWindow / 2;
    k[size_t(i)] = std::exp(-d * d / (2 * kSsimSigma * kSsimSigma));
    sum += k[size_t(i)];
  }
  for (double& v : k) v /= sum;
  return k;
}

std::vector<double> ssim_map(const io::ImageF& a, const io::ImageF& b) {
  require_same_rgb(a, b, "ssim");
  const int w = a.width, h = a.height;
  const size_t n = size_t(w) * size_t(h);
  const std::vector<double> k = ssim_window_1d();
  std::vector<double> map(n * 3);
  std::vector<double> x(n), y(n), xx(n), yy(n), xy(n);
  for (int c = 0; c < 3; ++c) {
    for (size_t i = 0; i < n; ++i) {
      x[i] = a.data[i * 3 + c];
      y[i] = b.data[i * 3 + c];
      xx[i] = x[i] * x[i];
      yy[i] = y[i] * y[i];
      xy[i] = x[i] * y[i];
    }
    const auto mx = blur(x, w, h, k), my = blur(y, w, h, k);
    const auto sxx = blur(xx, w, h, k), syy = blur(yy, w, h, k), sxy = blur(xy, w, h, k);
    for (size_t i = 0; i < n; ++i) {
      const double vx = sxx[i] - mx[i] * mx[i], vy = syy[i] - my[i] * my[i], cxy = sxy[i] - mx[i] * my[i];
      map[i * 3 + c] = ((2 * mx[i] * my[i] + kSsimC1) * (2 * cxy + kSsimC2)) /
                       ((mx[i] * mx[i] + my[i] * my[i] + kSsimC1) * (vx + vy + kSsimC2));
    }
  }
  return map;
}

double ssim(const io::ImageF& a, const io::ImageF& b) {
  const std::vector<double> map = ssim_map(a, b);
  double s = 0;
  for (double v : map) s += v;
  return s / double(map.size());
}

}  // namespace s4d::metrics
