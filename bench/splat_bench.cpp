#include "splat_bench.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "s4d/engine/buffer_from.h"
#include "s4d/engine/buffer.h"
#include "s4d/primitives/shader_pipeline.h"
#include "s4d/run/stage_times.h"
#include "s4d_splat.h"

namespace s4d::bench {

namespace {

constexpr std::array<float, 3> kBackground = {0.25f, 0.5f, 0.75f};

// Gradient outputs and a random RGB cotangent (an RGB-only loss, as in training).
struct DeviceGrads {
  splat::PerAttr<engine::Buffer, splat::kCloudAttrCount> grads;
  engine::Buffer v_rgb;

  DeviceGrads(engine::Context& ctx, const splat::GaussianParams& p, size_t pixels, uint32_t seed) {
    for (splat::Attr a : splat::kCloudAttrs)
      grads[a] = engine::Buffer(ctx, std::string("bench v_") + splat::attr_name(a),
                                size_t{p.count} * splat::attr_floats(a, p.sh_coeffs) * 4);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-1, 1);
    std::vector<float> v(3 * pixels);
    for (float& x : v) x = u(rng);
    v_rgb = engine::buffer_from(ctx, "bench v_rgb", v);
  }
  splat::GaussianGrads out() {
    splat::GaussianGrads g;
    for (splat::Attr a : splat::kCloudAttrs) g[a] = &grads[a];
    return g;
  }
  size_t bytes() const {
    size_t total = v_rgb.size();
    for (const engine::Buffer& b : grads.items) total += b.size();
    return total;
  }
};

double ms_between(std::chrono::steady_clock::time_point a, std::chrono::steady_clock::time_point b) {
  return std::chrono::duration<double, std::milli>(b - a).count();
}

// Largest |gpu - twin| over RGB and alpha; infinity when either holds a NaN or infinity.
double max_abs_diff(const std::vector<float>& gpu, const std::vector<float>& twin) {
  double worst = 0;
  for (size_t i = 0; i < gpu.size(); ++i) {
    const double d = std::abs(static_cast<double>(gpu[i]) - static_cast<double>(twin[i]));
    worst = std::isfinite(d) ? std::max(worst, d) : std::numeric_limits<double>::infinity();
  }
  return worst;
}

}  // namespace

PixelPairs count_pixel_pairs(engine::Context& ctx, const splat::Rasterizer& raster, size_t pixels) {
  const auto sum = [&](const engine::Buffer& b) {
    const std::vector<uint32_t> v = ctx.download<uint32_t>(b, pixels);
    return std::accumulate(v.begin(), v.end(), uint64_t{0});
  };
  return {.blended = sum(raster.contributors()), .evaluated = sum(raster.last_contributor())};
}

SplatTiming bench_splat(engine::Context& ctx, const SplatScene& scene, int repeats, bool backward, bool check_twin,
                        uint32_t seed, const splat::RasterizerOptions& options) {
  const SplatPoint point{.width = static_cast<uint32_t>(scene.camera.width),
                         .height = static_cast<uint32_t>(scene.camera.height),
                         .gaussians = static_cast<uint32_t>(scene.gaussians.size())};
  SplatTiming t{.point = point};
  const splat::Camera cam = to_gpu_camera(scene.camera);
  const size_t pixels = size_t{point.width} * point.height;
  const DeviceScene dev(ctx, scene.gaussians);
  std::optional<DeviceGrads> grads;
  if (backward) grads.emplace(ctx, dev.params, pixels, seed);
  splat::Rasterizer raster(ctx, "bench rasterizer", options);
  t.bwd_pixels = raster.backward_pixels();
  t.fwd_pixels = raster.forward_pixels();

  std::vector<double> fwd_ms, fwdbwd_ms;
  splat::RenderStats stats;
  engine::StageTimer timer(ctx, run::kStepStages);
  for (int r = -1; r < repeats; ++r) {  // run -1 grows the buffers and compiles pipelines; not counted
    const engine::StageTimer::Window window(r < 0 ? nullptr : &timer);
    const auto t0 = std::chrono::steady_clock::now();
    stats = raster.forward(dev.params, cam, kBackground);
    const auto t1 = std::chrono::steady_clock::now();
    if (backward) raster.backward(dev.params, {.v_rgb = &grads->v_rgb}, grads->out());
    const auto t2 = std::chrono::steady_clock::now();
    if (r < 0) continue;
    fwd_ms.push_back(ms_between(t0, t1));
    if (backward) fwdbwd_ms.push_back(ms_between(t0, t2));
  }
  t.stages = timer.totals();
  t.fwd = summarise_ms(std::move(fwd_ms));
  if (backward) t.fwdbwd = summarise_ms(std::move(fwdbwd_ms));
  t.instances = stats.instances;
  t.longest_tile_list = stats.longest_tile_list;
  t.tiles = primitives::ceil_div(point.width, S4D_TILE_SIZE) * primitives::ceil_div(point.height, S4D_TILE_SIZE);
  t.pixel_pairs_listed = uint64_t{stats.instances} * S4D_TILE_PIXELS;
  const PixelPairs pairs = count_pixel_pairs(ctx, raster, pixels);
  t.pixel_pairs_blended = pairs.blended;
  t.pixel_pairs_evaluated = pairs.evaluated;
  t.device_bytes = raster.device_bytes() + dev.bytes() + (grads ? grads->bytes() : 0);

  if (check_twin) {
    const ref::Image<float> img = ref::render_fwd(scene.gaussians, scene.camera, kBackground).second;
    t.twin_checked = true;
    t.twin_max_abs_diff = std::max(max_abs_diff(ctx.download<float>(raster.rgb(), 3 * pixels), img.rgb),
                                   max_abs_diff(ctx.download<float>(raster.alpha(), pixels), img.alpha));
    t.matches_twin = t.twin_max_abs_diff <= kTwinTolerance;
  }
  return t;
}

}  // namespace s4d::bench
