#include "s4d/synth/render.h"

#include <algorithm>
#include <atomic>
#include <limits>
#include <stdexcept>
#include <thread>

#include "s4d/synth/hash_rng.h"

namespace s4d::synth {
namespace {

struct RowResult {
  double min_depth = std::numeric_limits<double>::infinity();
  double max_depth = -std::numeric_limits<double>::infinity();
};

void render_row(const Scene& scene, const PinholeCamera& cam, double t, const RenderSettings& st, int y, float* out,
                float* alpha, RowResult& range) {
  const int n = st.samples_per_axis;
  const double inv = 1.0 / (n * n);
  for (int x = 0; x < cam.width; ++x) {
    const uint64_t pixel = static_cast<uint64_t>(y) * static_cast<uint64_t>(cam.width) + static_cast<uint64_t>(x);
    Vec3 sum{};
    int hits = 0;
    for (int k = 0; k < n * n; ++k) {
      const uint64_t h = hash_key(st.seed, pixel, static_cast<uint64_t>(k));
      const double jx = unit_double(h), jy = unit_double(mix64(h));
      const double px = x + ((k % n) + jx) / n, py = y + ((k / n) + jy) / n;
      const Ray ray = cam.ray(px, py);
      if (const auto hit = trace(scene, ray, t)) {
        sum = sum + shade(scene, *hit, ray.dir);
        ++hits;
        const double depth = cam.view_depth(hit->point);
        range.min_depth = std::min(range.min_depth, depth);
        range.max_depth = std::max(range.max_depth, depth);
      } else {
        sum = sum + sky_colour(scene);
      }
    }
    out[3 * x + 0] = static_cast<float>(sum[0] * inv);
    out[3 * x + 1] = static_cast<float>(sum[1] * inv);
    out[3 * x + 2] = static_cast<float>(sum[2] * inv);
    alpha[x] = static_cast<float>(hits * inv);
  }
}

}  // namespace

RenderedView render_view(const Scene& scene, const PinholeCamera& camera, double t, const RenderSettings& settings) {
  if (settings.samples_per_axis < 1) throw std::invalid_argument("render_view: samples_per_axis must be >= 1");
  if (camera.width <= 0 || camera.height <= 0 || !(camera.focal > 0))
    throw std::invalid_argument("render_view: the camera needs a positive size and focal length");
  RenderedView view;
  view.width = camera.width;
  view.height = camera.height;
  view.rgb.resize(static_cast<size_t>(camera.width) * static_cast<size_t>(camera.height) * 3);
  view.alpha.resize(static_cast<size_t>(camera.width) * static_cast<size_t>(camera.height));
  const unsigned hw = settings.threads > 0 ? static_cast<unsigned>(settings.threads)
                                           : std::max(1u, std::thread::hardware_concurrency());
  const unsigned count = std::min(hw, static_cast<unsigned>(camera.height));
  // Rows are handed out one at a time so uneven rows (the sheet's ray march) balance out.
  std::atomic<int> next_row{0};
  std::vector<RowResult> ranges(count);
  auto work = [&](unsigned w) {
    for (int y = next_row++; y < camera.height; y = next_row++)
      render_row(scene, camera, t, settings, y, view.rgb.data() + static_cast<size_t>(y) * static_cast<size_t>(camera.width) * 3,
                 view.alpha.data() + static_cast<size_t>(y) * static_cast<size_t>(camera.width), ranges[w]);
  };
  std::vector<std::thread> pool;
  for (unsigned w = 1; w < count; ++w) pool.emplace_back(work, w);
  work(0);
  for (auto& th : pool) th.join();
  view.min_depth = std::numeric_limits<double>::infinity();
  view.max_depth = -std::numeric_limits<double>::infinity();
  for (const RowResult& r : ranges) {
    view.min_depth = std::min(view.min_depth, r.min_depth);
    view.max_depth = std::max(view.max_depth, r.max_depth);
  }
  return view;
}

}  // namespace s4d::synth
