// UIQM variant A: FUnIE-GAN Evaluation/uqim_utils.py, Python-3 port (uiqm.h lists the conventions).
#include <algorithm>
#include <cmath>

#include "s4d/metrics/uiqm.h"

namespace s4d::metrics::detail {

namespace {

double trimmed_mean(std::vector<double> x) {
  std::sort(x.begin(), x.end());
  const double k = double(x.size());
  const double t_l = std::ceil(0.1 * k), t_r = std::floor(0.1 * k);
  double sum = 0;
  for (size_t i = size_t(t_l) + 1; i < size_t(k - t_r); ++i) sum += x[i];
  return sum / (k - t_l - t_r);
}

double variance_about(const std::vector<double>& x, double mu) {
  double s = 0;
  for (double v : x) s += (v - mu) * (v - mu);
  return s / double(x.size());
}

double uicm(const LevelPlanes& p) {
  const size_t n = p.c[0].size();
  std::vector<double> rg(n), yb(n);
  for (size_t i = 0; i < n; ++i) {
    rg[i] = p.c[0][i] - p.c[1][i];
    yb[i] = (p.c[0][i] + p.c[1][i]) / 2 - p.c[2][i];
  }
  const double mu_rg = trimmed_mean(rg), mu_yb = trimmed_mean(yb);
  return -0.0268 * std::sqrt(mu_rg * mu_rg + mu_yb * mu_yb) +
         0.1586 * std::sqrt(variance_about(rg, mu_rg) + variance_about(yb, mu_yb));
}

// scipy.ndimage.sobel along both axes, mode 'reflect' (index -1 reads 0, index n reads n-1),
// magnitude rescaled to max 255; all zero for a flat plane.
std::vector<double> sobel_magnitude(const std::vector<double>& v, int w, int h) {
  auto at = [&](int x, int y) {
    x = x < 0 ? 0 : (x >= w ? w - 1 : x);
    y = y < 0 ? 0 : (y >= h ? h - 1 : y);
    return v[size_t(y) * w + x];
  };
  std::vector<double> mag(v.size());
  double peak = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const double dy = (at(x - 1, y + 1) + 2 * at(x, y + 1) + at(x + 1, y + 1)) -
                        (at(x - 1, y - 1) + 2 * at(x, y - 1) + at(x + 1, y - 1));
      const double dx = (at(x + 1, y - 1) + 2 * at(x + 1, y) + at(x + 1, y + 1)) -
                        (at(x - 1, y - 1) + 2 * at(x - 1, y) + at(x - 1, y + 1));
      const double m = std::hypot(dx, dy);
      mag[size_t(y) * w + x] = m;
      peak = std::max(peak, m);
    }
  if (peak > 0)
    for (double& m : mag) m *= 255.0 / peak;
  return mag;
}

double eme10(const std::vector<double>& e, int w, int h) {
  const int k1 = w / 10, k2 = h / 10;
  double val = 0;
  for (int bx = 0; bx < k1; ++bx)
    for (int by = 0; by < k2; ++by) {
      double lo = e[size_t(by * 10) * w + bx * 10], hi = lo;
      for (int y = by * 10; y < by * 10 + 10; ++y)
        for (int x = bx * 10; x < bx * 10 + 10; ++x) lo = std::min(lo, e[size_t(y) * w + x]), hi = std::max(hi, e[size_t(y) * w + x]);
      if (lo != 0 && hi != 0) val += std::log(hi / lo);
    }
  return 2.0 / (double(k1) * double(k2)) * val;
}

double uism(const LevelPlanes& p) {
  const double lambda[3] = {0.299, 0.587, 0.144};
  double s = 0;
  for (int c = 0; c < 3; ++c) {
    std::vector<double> edge = sobel_magnitude(p.c[c], p.width, p.height);
    for (size_t i = 0; i < edge.size(); ++i) edge[i] *= p.c[c][i];
    s += lambda[c] * eme10(edge, p.width, p.height);
  }
  return s;
}

double uiconm(const LevelPlanes& p) {
  const int w = p.width, k1 = w / 10, k2 = p.height / 10;
  double val = 0;
  for (int bx = 0; bx < k1; ++bx)
    for (int by = 0; by < k2; ++by) {
      double lo = p.c[0][size_t(by * 10) * w + bx * 10], hi = lo;
      for (int c = 0; c < 3; ++c)
        for (int y = by * 10; y < by * 10 + 10; ++y)
          for (int x = bx * 10; x < bx * 10 + 10; ++x)
            lo = std::min(lo, p.c[c][size_t(y) * w + x]), hi = std::max(hi, p.c[c][size_t(y) * w + x]);
      const double top = hi - lo, bot = hi + lo;
      if (top != 0 && bot != 0) val += (top / bot) * std::log(top / bot);
    }
  return -1.0 / ((w / 10.0) * (p.height / 10.0)) * val;
}

}  // namespace

UiqmParts uiqm_funie_gan(const LevelPlanes& p) { return {uicm(p), uism(p), uiconm(p)}; }

}  // namespace s4d::metrics::detail
