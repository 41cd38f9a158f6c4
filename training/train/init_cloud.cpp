#include "s4d/train/init_cloud.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <unordered_map>

namespace s4d::train {

namespace {

constexpr float kShC0 = 0.28209479177387814f;  // Y_0^0: rgb = 0.5 + C0 * dc
constexpr float kInitOpacity = 0.1f;

struct Grid {
  float cell;
  float lo[3];
  std::unordered_map<uint64_t, std::vector<uint32_t>> cells;

  static uint64_t key(int64_t x, int64_t y, int64_t z) {
    return (uint64_t(x & 0x1FFFFF) << 42) | (uint64_t(y & 0x1FFFFF) << 21) | uint64_t(z & 0x1FFFFF);
  }
  int64_t coord(float v, int axis) const { return static_cast<int64_t>(std::floor((v - lo[axis]) / cell)); }
};

}  // namespace

std::vector<float> mean_sq_dist_3nn(const std::vector<float>& p) {
  const size_t n = p.size() / 3;
  std::vector<float> out(n, 0.0f);
  if (n < 2) return out;
  Grid g{};
  float hi[3];
  for (int a = 0; a < 3; ++a) {
    g.lo[a] = hi[a] = p[size_t(a)];
    for (size_t i = 0; i < n; ++i) g.lo[a] = std::min(g.lo[a], p[i * 3 + a]), hi[a] = std::max(hi[a], p[i * 3 + a]);
  }
  // About 2 points per cell for a surface-like cloud: cell = sqrt(area / n) with area ~ the largest face.
  const float ext[3] = {hi[0] - g.lo[0], hi[1] - g.lo[1], hi[2] - g.lo[2]};
  const float face = std::max({ext[0] * ext[1], ext[0] * ext[2], ext[1] * ext[2], 1e-12f});
  g.cell = std::max(std::sqrt(2.0f * face / float(n)), 1e-6f);
  for (size_t i = 0; i < n; ++i)
    g.cells[Grid::key(g.coord(p[i * 3], 0), g.coord(p[i * 3 + 1], 1), g.coord(p[i * 3 + 2], 2))].push_back(uint32_t(i));
  const int k = std::min<int>(3, int(n) - 1);
  for (size_t i = 0; i < n; ++i) {
    const int64_t c[3] = {g.coord(p[i * 3], 0), g.coord(p[i * 3 + 1], 1), g.coord(p[i * 3 + 2], 2)};
    float best[3] = {INFINITY, INFINITY, INFINITY};
    // Grow the searched shell until the k-th best is closer than any unsearched cell can be.
    for (int r = 0;; ++r) {
      for (int64_t dx = -r; dx <= r; ++dx)
        for (int64_t dy = -r; dy <= r; ++dy)
          for (int64_t dz = -r; dz <= r; ++dz) {
            if (std::max({std::abs(dx), std::abs(dy), std::abs(dz)}) != r) continue;  // the shell only
            auto it = g.cells.find(Grid::key(c[0] + dx, c[1] + dy, c[2] + dz));
            if (it == g.cells.end()) continue;
            for (uint32_t j : it->second) {
              if (j == i) continue;
              float d2 = 0;
              for (int a = 0; a < 3; ++a) d2 += (p[j * 3 + a] - p[i * 3 + a]) * (p[j * 3 + a] - p[i * 3 + a]);
              int slot = k - 1;  // insertion into the sorted k best
              if (d2 >= best[slot]) continue;
              for (; slot > 0 && best[slot - 1] > d2; --slot) best[slot] = best[slot - 1];
              best[slot] = d2;
            }
          }
      const float reach = float(r) * g.cell;  // every point within this distance has been seen
      if (best[k - 1] <= reach * reach) break;
    }
    float sum = 0;
    for (int m = 0; m < k; ++m) sum += best[m];
    out[i] = sum / float(k);
  }
  return out;
}

io::GaussianCloud cloud_from_points(const std::vector<float>& points, const std::vector<float>& colors, int sh_degree) {
  if (points.empty() || points.size() % 3 != 0 || colors.size() != points.size())
    throw std::invalid_argument("initial points: need [P, 3] positions and [P, 3] colours, got " +
                                std::to_string(points.size()) + " and " + std::to_string(colors.size()) + " floats");
  for (size_t i = 0; i < points.size(); ++i)
    if (!std::isfinite(points[i]) || !std::isfinite(colors[i]))
      throw std::invalid_argument("initial points: point " + std::to_string(i / 3) + " is not finite");
  const size_t n = points.size() / 3, k = size_t((sh_degree + 1) * (sh_degree + 1));
  const std::vector<float> d2 = mean_sq_dist_3nn(points);
  io::GaussianCloud c;
  c.sh_degree = sh_degree;
  c.means = points;
  c.log_scales.resize(n * 3);
  c.quats.assign(n * 4, 0.0f);
  c.opacity_logits.assign(n, std::log(kInitOpacity / (1 - kInitOpacity)));
  c.sh.assign(n * k * 3, 0.0f);
  for (size_t i = 0; i < n; ++i) {
    const float log_s = 0.5f * std::log(std::max(d2[i], 1e-7f));
    for (int a = 0; a < 3; ++a) {
      c.log_scales[i * 3 + a] = log_s;
      c.sh[i * k * 3 + a] = (colors[i * 3 + a] - 0.5f) / kShC0;
    }
    c.quats[i * 4] = 1.0f;
  }
  return c;
}

io::GaussianCloud initial_cloud(const data::Dataset& dataset, int sh_degree, uint32_t random_points, uint32_t seed) {
  if (!dataset.points.empty()) return cloud_from_points(dataset.points, dataset.colors, sh_degree);
  if (random_points == 0) throw std::invalid_argument(dataset.root.string() + ": no points3D.ply and no random points asked for");
  // The cameras look at the scene: centre the cube on the point nearest to all optical axes.
  double a[3][3] = {}, b[3] = {};
  size_t train = 0;
  for (const data::View& v : dataset.views) {
    if (v.test) continue;
    const auto& m = v.camera.world_to_cam;
    const double d[3] = {m[8], m[9], m[10]};  // forward axis in world = third row of R
    const double o[3] = {-(m[0] * m[3] + m[4] * m[7] + m[8] * m[11]), -(m[1] * m[3] + m[5] * m[7] + m[9] * m[11]),
                         -(m[2] * m[3] + m[6] * m[7] + m[10] * m[11])};
    for (int r = 0; r < 3; ++r)
      for (int s = 0; s < 3; ++s) {
        const double proj = (r == s ? 1.0 : 0.0) - d[r] * d[s];
        a[r][s] += proj;
        b[r] += proj * o[s];
      }
    ++train;
  }
  double centre[3] = {0, 0, 0};
  const double det = a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
                     a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
  if (train >= 2 && std::abs(det) > 1e-9) {  // Cramer's rule; parallel axes leave the origin
    for (int c = 0; c < 3; ++c) {
      double m[3][3];
      for (int r = 0; r < 3; ++r)
        for (int s = 0; s < 3; ++s) m[r][s] = s == c ? b[r] : a[r][s];
      centre[c] = (m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                   m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])) / det;
    }
  }
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  const float half = static_cast<float>(dataset.extent);
  std::vector<float> pts(size_t{random_points} * 3), cols(size_t{random_points} * 3);
  for (size_t i = 0; i < pts.size(); ++i) {
    pts[i] = float(centre[i % 3]) + (2 * unit(rng) - 1) * half;
    cols[i] = unit(rng);
  }
  return cloud_from_points(pts, cols, sh_degree);
}

}  // namespace s4d::train
