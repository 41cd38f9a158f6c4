// IRLS for sum_p || R_p X - z_p ||^r: each step fixes w_p = max(|| R_p X - z_p ||, eps)^(r - 2) from
// the current X and solves the weighted least squares, whose normal equations are diagonal (R_p^T R_p
// only selects pixels): X(i) = sum_p w_p z_p(i) / sum_p w_p over the patches covering pixel i.
#include "s4d/frame_stylizers/robust_aggregation.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace s4d::frame_stylizers {

namespace {

double patch_distance(const io::ImageF& image, int n, const PlacedPatch& p) {
  const int c = image.channels;
  double sum = 0;
  for (int dy = 0; dy < n; ++dy) {
    const float* row = image.data.data() + (static_cast<size_t>(p.y + dy) * image.width + p.x) * c;
    const float* z = p.values + static_cast<size_t>(dy) * n * c;
    for (int i = 0; i < n * c; ++i) sum += static_cast<double>(row[i] - z[i]) * (row[i] - z[i]);
  }
  return std::sqrt(sum);
}

}  // namespace

io::ImageF robust_aggregate(const io::ImageF& current, int patch_size, const std::vector<PlacedPatch>& patches,
                            const AggregationSettings& settings) {
  const int n = patch_size;
  if (n <= 0 || current.width <= 0 || current.height <= 0 || current.channels <= 0 ||
      current.data.size() != static_cast<size_t>(current.width) * current.height * current.channels)
    throw std::invalid_argument("robust_aggregate: bad image or patch size " + std::to_string(n));
  for (const PlacedPatch& p : patches)
    if (!p.values || p.x < 0 || p.y < 0 || p.x + n > current.width || p.y + n > current.height)
      throw std::invalid_argument("robust_aggregate: patch at (" + std::to_string(p.x) + ", " + std::to_string(p.y) +
                                  ") is null or outside the " + std::to_string(current.width) + "x" +
                                  std::to_string(current.height) + " image");
  const int c = current.channels;
  io::ImageF x = current;
  std::vector<double> num(x.data.size()), den(static_cast<size_t>(x.width) * x.height);
  for (int step = 0; step < settings.iterations; ++step) {
    std::fill(num.begin(), num.end(), 0.0);
    std::fill(den.begin(), den.end(), 0.0);
    for (const PlacedPatch& p : patches) {
      const double w = std::pow(std::max(patch_distance(x, n, p), static_cast<double>(settings.eps)),
                                static_cast<double>(settings.r) - 2.0);
      for (int dy = 0; dy < n; ++dy) {
        const size_t pixel0 = static_cast<size_t>(p.y + dy) * x.width + p.x;
        const float* z = p.values + static_cast<size_t>(dy) * n * c;
        for (int dx = 0; dx < n; ++dx) {
          den[pixel0 + dx] += w;
          for (int k = 0; k < c; ++k) num[(pixel0 + dx) * c + k] += w * z[dx * c + k];
        }
      }
    }
    for (size_t i = 0; i < den.size(); ++i)
      if (den[i] > 0)
        for (int k = 0; k < c; ++k) x.data[i * c + k] = static_cast<float>(num[i * c + k] / den[i]);
  }
  return x;
}

}  // namespace s4d::frame_stylizers
