#include "s4d/train/missing_content.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "s4d/util/vec3.h"

namespace s4d::train {
namespace {

// Camera centre and the world direction of pixel point (x, y) (OpenCV axes: R p + t).
struct PixelRay {
  Vec3 origin, dir;
};

PixelRay pixel_ray(const io::CameraView& c, double x, double y) {
  const auto& m = c.world_to_cam;
  auto r = [&](int i, int j) { return m[size_t(i * 4 + j)]; };
  const Vec3 t{r(0, 3), r(1, 3), r(2, 3)};
  Vec3 origin{}, dir{};
  const Vec3 d_cam{(x - c.cx) / c.fx, (y - c.cy) / c.fy, 1.0};
  for (int j = 0; j < 3; ++j) {
    origin[j] = -(r(0, j) * t[0] + r(1, j) * t[1] + r(2, j) * t[2]);  // -R^T t
    dir[j] = r(0, j) * d_cam[0] + r(1, j) * d_cam[1] + r(2, j) * d_cam[2];  // R^T d
  }
  return {origin, dir};  // dir has unit z in camera space: the ray parameter is the view depth
}

// Image point and depth of a world point; depth <= 0 behind the camera.
std::array<double, 3> project(const io::CameraView& c, const Vec3& p) {
  const auto& m = c.world_to_cam;
  double q[3];
  for (int i = 0; i < 3; ++i) q[i] = m[size_t(i * 4)] * p[0] + m[size_t(i * 4 + 1)] * p[1] + m[size_t(i * 4 + 2)] * p[2] + m[size_t(i * 4 + 3)];
  if (q[2] <= 1e-9) return {0, 0, q[2]};
  return {c.fx * q[0] / q[2] + c.cx, c.fy * q[1] / q[2] + c.cy, q[2]};
}

// Bilinear colour at image point (x, y) (pixel centres at +0.5), clamped at the borders.
void bilinear(const io::ImageF& im, double x, double y, float out[3]) {
  const double fx = x - 0.5, fy = y - 0.5;
  const int x0 = static_cast<int>(std::floor(fx)), y0 = static_cast<int>(std::floor(fy));
  const double ax = fx - x0, ay = fy - y0;
  const size_t ch = size_t(im.channels);
  for (int k = 0; k < 3; ++k) out[k] = 0;
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 2; ++i) {
      const int px = std::clamp(x0 + i, 0, im.width - 1), py = std::clamp(y0 + j, 0, im.height - 1);
      const double w = (i ? ax : 1 - ax) * (j ? ay : 1 - ay);
      const size_t p = (size_t(py) * size_t(im.width) + size_t(px)) * ch;
      for (size_t k = 0; k < 3; ++k) out[k] += static_cast<float>(w * im.data[p + std::min<size_t>(k, ch - 1)]);
    }
}

// Mean colour of a 3x3 pixel neighbourhood around image point (x, y), sampled bilinearly so that
// sub-pixel shifts along the ray change it smoothly; false outside the image.
bool patch_mean(const io::ImageF& im, double x, double y, float out[3]) {
  if (x < 0 || y < 0 || x >= im.width || y >= im.height) return false;
  float sum[3] = {0, 0, 0}, c[3];
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      bilinear(im, x + dx, y + dy, c);
      for (int k = 0; k < 3; ++k) sum[k] += c[k];
    }
  for (int k = 0; k < 3; ++k) out[k] = sum[k] / 9;
  return true;
}

// The ray's parameter range inside the box (slab test); nullopt when it misses.
std::optional<std::pair<double, double>> clip(const PixelRay& r, const std::array<float, 3>& lo, const std::array<float, 3>& hi) {
  double s0 = 1e-6, s1 = std::numeric_limits<double>::infinity();
  for (int a = 0; a < 3; ++a) {
    if (std::abs(r.dir[a]) < 1e-12) {
      if (r.origin[a] < lo[a] || r.origin[a] > hi[a]) return std::nullopt;
      continue;
    }
    double u = (lo[a] - r.origin[a]) / r.dir[a], v = (hi[a] - r.origin[a]) / r.dir[a];
    if (u > v) std::swap(u, v);
    s0 = std::max(s0, u), s1 = std::min(s1, v);
  }
  if (!(s0 < s1)) return std::nullopt;
  return std::pair{s0, s1};
}

}  // namespace

std::vector<MissedPixel> missed_pixels(const io::ImageF& render, const io::ImageF& truth, const SeedSettings& s) {
  std::vector<MissedPixel> out;
  const uint32_t cell = std::max<uint32_t>(1, s.cell);
  const size_t rc = size_t(render.channels), tc = size_t(truth.channels);
  for (int by = 0; by < truth.height; by += int(cell))
    for (int bx = 0; bx < truth.width; bx += int(cell)) {
      MissedPixel worst{};
      for (int y = by; y < std::min(truth.height, by + int(cell)); ++y)
        for (int x = bx; x < std::min(truth.width, bx + int(cell)); ++x) {
          const size_t p = size_t(y) * size_t(truth.width) + size_t(x);
          float e = 0;
          for (size_t k = 0; k < 3; ++k) e += std::abs(render.data[p * rc + k] - truth.data[p * tc + k]);
          e /= 3;
          if (e > worst.error) worst = {uint32_t(x), uint32_t(y), e};
        }
      if (worst.error > s.error_threshold) out.push_back(worst);
    }
  std::sort(out.begin(), out.end(), [](const MissedPixel& a, const MissedPixel& b) {
    return a.error != b.error ? a.error > b.error : (a.y != b.y ? a.y < b.y : a.x < b.x);
  });
  if (out.size() > s.max_seeds) out.resize(s.max_seeds);
  return out;
}

std::optional<double> consistent_depth(const ViewImage& source, double x, double y, const std::vector<ViewImage>& others,
                                       const std::array<float, 3>& box_lo, const std::array<float, 3>& box_hi,
                                       const SeedSettings& s) {
  if (others.empty()) return std::nullopt;
  const PixelRay ray = pixel_ray(source.camera, x, y);
  const auto range = clip(ray, box_lo, box_hi);
  if (!range) return std::nullopt;
  float colour[3];
  if (!patch_mean(*source.image, x, y, colour)) return std::nullopt;
  const size_t need = (others.size() + 1) / 2;
  double best = std::numeric_limits<double>::infinity(), best_depth = 0, cost_sum = 0;
  uint32_t costs = 0;
  const uint32_t n = std::max<uint32_t>(2, s.depth_samples);
  for (uint32_t k = 0; k < n; ++k) {
    const double depth = range->first + (range->second - range->first) * (k + 0.5) / n;
    const Vec3 p{ray.origin[0] + ray.dir[0] * depth, ray.origin[1] + ray.dir[1] * depth, ray.origin[2] + ray.dir[2] * depth};
    double cost = 0;
    size_t seen = 0;
    for (const ViewImage& o : others) {
      const auto q = project(o.camera, p);
      float c[3];
      if (q[2] <= 0 || !patch_mean(*o.image, q[0], q[1], c)) continue;
      cost += (std::abs(c[0] - colour[0]) + std::abs(c[1] - colour[1]) + std::abs(c[2] - colour[2])) / 3;
      ++seen;
    }
    if (seen < need) continue;
    // A view the point falls outside of gives no agreement: it counts as a mismatch at the
    // threshold, so a depth all views agree on beats a lucky match in one.
    cost = (cost + double(others.size() - seen) * s.error_threshold) / double(others.size());
    cost_sum += cost, ++costs;
    if (cost < best) best = cost, best_depth = depth;
  }
  // A depth only where the ray has one: the best must agree within the threshold and stand out
  // from the ray's mean (a flat cost, as over a textureless region, places nothing).
  if (!(best <= s.error_threshold) || !(best <= s.distinct * cost_sum / costs)) return std::nullopt;
  return best_depth;
}

std::vector<Seed> find_missing_content(const ViewImage& source, const RenderedView& render, const std::vector<ViewImage>& others,
                                       const std::array<float, 3>& box_lo, const std::array<float, 3>& box_hi,
                                       const SeedSettings& s) {
  std::vector<Seed> seeds;
  const io::ImageF& truth = *source.image;
  const size_t tc = size_t(truth.channels);
  for (const MissedPixel& m : missed_pixels(*render.rgb, truth, s)) {
    const size_t p = size_t(m.y) * size_t(truth.width) + size_t(m.x);
    const double px = m.x + 0.5, py = m.y + 0.5;
    // Missed content is what the model does not cover; a wrong colour where it does is left to
    // gradient-driven growth. A faint cover (a smudge) lends its depth when the sweep finds none.
    const float alpha = (*render.alpha)[p];
    if (alpha >= s.covered_alpha) continue;
    std::optional<double> depth = consistent_depth(source, px, py, others, box_lo, box_hi, s);
    const bool from_render = !depth && alpha >= s.faint_alpha;
    if (from_render) depth = (*render.depth)[p] / alpha;
    if (!depth || !(*depth > 0)) continue;
    const PixelRay ray = pixel_ray(source.camera, px, py);
    Seed seed;
    for (int a = 0; a < 3; ++a) {
      seed.position[size_t(a)] = static_cast<float>(ray.origin[size_t(a)] + ray.dir[size_t(a)] * *depth);
      seed.colour[size_t(a)] = truth.data[p * tc + std::min<size_t>(size_t(a), tc - 1)];
    }
    // Half the cell's footprint: neighbouring seeds overlap like a densified surface.
    seed.scale = static_cast<float>(0.5 * s.cell * *depth / source.camera.fx);
    seed.x = m.x, seed.y = m.y, seed.error = m.error, seed.from_render_depth = from_render;
    seeds.push_back(seed);
  }
  return seeds;
}

}  // namespace s4d::train
