// Speed of the GPU rasterizer (s4d::splat::Rasterizer) on a scene (splat_scene.h): forward and
// forward+backward wall-clock time, the time of each stage (project, sort, raster, backward),
// tile-list and pixel-pair counts and device memory, with an optional check of the forward image
// against the CPU twin.
#pragma once
#include <cstdint>

#include "s4d/engine/context.h"
#include "s4d/engine/stage_timer.h"
#include "s4d/splat/rasterizer.h"
#include "splat_scene.h"
#include "timing.h"

namespace s4d::bench {

struct SplatPoint {
  uint32_t width = 0, height = 0, gaussians = 0;
};

struct SplatTiming {
  SplatPoint point;
  // Wall clock around forward() and forward() + backward(), which both submit and wait; taken from
  // the same runs. fwdbwd is empty unless the backward was measured.
  Timing fwd, fwdbwd;
  uint32_t instances = 0, tiles = 0, longest_tile_list = 0;
  uint32_t bwd_pixels = 0;  // the backward kernel's pixels per invocation (its variant)
  uint32_t fwd_pixels = 0;  // the forward kernel's
  // (pixel, Gaussian) pairs the tile lists hold: instances * 256, every pixel of a tile counted up to
  // the end of its list. Early termination means fewer are actually visited.
  uint64_t pixel_pairs_listed = 0;
  uint64_t pixel_pairs_blended = 0;  // pairs that contributed to a pixel (sum of per-pixel contributors)
  // Pairs a pixel's blend loop reached, up to its last contributor (sum of the per-pixel `last`):
  // what the backward replays.
  uint64_t pixel_pairs_evaluated = 0;
  engine::StageTotals stages;  // over the measured runs (not the warm-up)
  size_t device_bytes = 0;           // rasterizer buffers + the scene, gradient and cotangent buffers
  bool twin_checked = false;
  bool matches_twin = false;       // forward RGB and alpha within kTwinTolerance of ref::render_fwd
  double twin_max_abs_diff = 0;
};

// Maximum absolute difference allowed between the GPU forward image and the CPU twin's. The twin
// runs the same float operations in the same order; on lavapipe (Mesa 22.3.6) the two agree to
// 3.6e-7 on the 128x128 random scene (3.0e-7 at 64x48), and to 5.7e-5 on the 128x128 peer scene,
// where one pixel's transmittance lands on the other side of the 1e-4 stop threshold (one Gaussian
// blended more or less, weighted by T < 1e-4). 1e-4 leaves room for other drivers' exp (the
// Vulkan spec allows 3 + 2|x| ULP) and fused multiply-adds, while a Gaussian binned, sorted or
// blended wrongly moves pixels by far more.
inline constexpr double kTwinTolerance = 1e-4;

// Runs one warm-up and `repeats` measured forward passes (each followed by a backward when
// `backward`) of `scene` on a fresh rasterizer. Throws what the rasterizer or the allocator throws
// when the scene exceeds the device's memory or limits. `seed` draws the image cotangent.
SplatTiming bench_splat(engine::Context& ctx, const SplatScene& scene, int repeats, bool backward, bool check_twin,
                        uint32_t seed = 1, const splat::RasterizerOptions& options = {});

// Pixel-Gaussian pairs of the rasterizer's last forward at `pixels` pixels.
struct PixelPairs {
  uint64_t blended = 0, evaluated = 0;
};
PixelPairs count_pixel_pairs(engine::Context& ctx, const splat::Rasterizer& raster, size_t pixels);

}  // namespace s4d::bench
