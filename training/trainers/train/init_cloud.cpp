#include "s4d/train/init_cloud.h"

#include "s4d/data/camera_geometry.h"

#include <array>
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

void voxel_downsample(std::vector<float>& points, std::vector<float>& colors, double voxel) {
  struct Sum {
    double p[3] = {0, 0, 0}, c[3] = {0, 0, 0};
    size_t n = 0;
  };
  std::unordered_map<uint64_t, size_t> slot;
  std::vector<Sum> sums;
  for (size_t i = 0; i < points.size() / 3; ++i) {
    uint64_t key = 0;
    for (size_t a = 0; a < 3; ++a) key = key << 21 | (uint64_t(int64_t(std::floor(points[i * 3 + a] / voxel))) & 0x1FFFFF);
    const auto [it, added] = slot.try_emplace(key, sums.size());
    if (added) sums.emplace_back();
    Sum& sum = sums[it->second];
    for (size_t a = 0; a < 3; ++a) sum.p[a] += points[i * 3 + a], sum.c[a] += colors[i * 3 + a];
    ++sum.n;
  }
  points.resize(sums.size() * 3);
  colors.resize(sums.size() * 3);
  for (size_t v = 0; v < sums.size(); ++v) {
    for (size_t a = 0; a < 3; ++a) {
      points[v * 3 + a] = float(sums[v].p[a] / double(sums[v].n));
      colors[v * 3 + a] = float(sums[v].c[a] / double(sums[v].n));
    }
  }
}

namespace {

constexpr size_t kFrustumCameras = 64;    // training cameras a random candidate is tested against (spread)
constexpr double kFrustumShare = 0.8;     // share of them that must see it
constexpr uint32_t kCandidatesPerPoint = 200;  // gives up past this many candidates per wanted point

}  // namespace

io::GaussianCloud initial_cloud(const data::Dataset& dataset, int sh_degree, uint32_t random_points, uint32_t max_points,
                                uint32_t seed, InitReport* report) {
  InitReport r;
  if (!dataset.points.empty()) {
    std::vector<float> points = dataset.points, colors = dataset.colors;
    r.method = "points";
    r.file = dataset.points_file.string();
    r.file_points = points.size() / 3;
    if (max_points > 0 && points.size() / 3 > max_points) {
      float lo[3], hi[3];
      for (size_t a = 0; a < 3; ++a) {
        lo[a] = hi[a] = points[a];
        for (size_t i = 0; i < points.size() / 3; ++i) lo[a] = std::min(lo[a], points[i * 3 + a]), hi[a] = std::max(hi[a], points[i * 3 + a]);
      }
      // Start where a surface cloud of the box's size would fit, then grow by 25 % until it does.
      double voxel = std::max(1e-6, std::hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]) / 4096.0);
      std::vector<float> p = points, c = colors;
      while (p.size() / 3 > max_points) {
        p = points, c = colors;
        voxel_downsample(p, c, voxel);
        r.voxel = voxel;
        voxel *= 1.25;
      }
      points.swap(p), colors.swap(c);
    }
    r.points = points.size() / 3;
    if (report) *report = r;
    return cloud_from_points(points, colors, sh_degree);
  }
  if (random_points == 0) throw std::invalid_argument(dataset.root.string() + ": no point cloud and no random points asked for");
  std::vector<const io::CameraView*> train, cameras;
  for (const data::View& v : dataset.views)
    if (!v.test) train.push_back(&v.camera);
  const size_t used = std::min(kFrustumCameras, train.size());
  for (size_t i = 0; i < used; ++i) cameras.push_back(train[i * train.size() / used]);
  // The region the cameras look at; the origin when their axes are parallel.
  const Vec3 centre = data::nearest_to_optical_axes(train).value_or(Vec3{0, 0, 0});
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  const float half = static_cast<float>(dataset.extent);
  std::vector<float> pts, cols;
  uint64_t tried = 0;
  const uint64_t max_tries = uint64_t{random_points} * kCandidatesPerPoint;
  while (pts.size() / 3 < random_points && tried < max_tries) {
    ++tried;
    float p[3];
    for (size_t a = 0; a < 3; ++a) p[a] = float(centre[a]) + (2 * unit(rng) - 1) * half;
    size_t seen = 0;
    for (const io::CameraView* c : cameras) seen += data::sees(*c, {p[0], p[1], p[2]}) ? 1 : 0;
    if (double(seen) < kFrustumShare * double(cameras.size())) continue;
    for (size_t a = 0; a < 3; ++a) pts.push_back(p[a]), cols.push_back(unit(rng));
  }
  if (pts.empty())
    throw std::runtime_error(dataset.root.string() + ": no point of the cameras' look-at region is seen by " +
                             std::to_string(int(kFrustumShare * 100)) + " % of the training cameras; give a point cloud");
  r.method = "random-frustum";
  r.points = pts.size() / 3;
  r.acceptance = double(r.points) / double(tried);
  if (report) *report = r;
  return cloud_from_points(pts, cols, sh_degree);
}

}  // namespace s4d::train
