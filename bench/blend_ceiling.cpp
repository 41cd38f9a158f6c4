#include "blend_ceiling.h"

#include <algorithm>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "s4d/engine/buffer_from.h"
#include "s4d/engine/buffer.h"
#include "s4d/engine/recorder.h"
#include "s4d/engine/timestamps.h"
#include "s4d/primitives/shader_pipeline.h"
#include "s4d_bench.h"
#include "s4d_splat.h"

namespace s4d::bench {

namespace {

using primitives::ceil_div;

struct Entries {
  std::vector<float> xy, conic_opacity, color_depth;  // [L*2], [L*4], [L*4]
};

// Wide, faint entries: means inside the tile, A, C <= 1.5e-4 and |B| <= 2e-5 keep G >= 0.96 over
// the tile, so alpha = opacity * G stays within [0.00403, 0.0044]: above 1/255 (never skipped) and
// low enough that (1 - 0.0044)^2048 > 1e-4 (never ends a pixel early).
Entries make_entries(uint32_t n, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1, 1), u01(0, 1);
  Entries e;
  for (uint32_t i = 0; i < n; ++i) {
    for (int k = 0; k < 2; ++k) e.xy.push_back(S4D_TILE_SIZE * u01(rng));
    for (float v : {1e-4f + 5e-5f * u(rng), 2e-5f * u(rng), 1e-4f + 5e-5f * u(rng), 0.0042f + 0.0002f * u01(rng)})
      e.conic_opacity.push_back(v);
    for (float v : {u01(rng), u01(rng), u01(rng), 2.0f + 8.0f * u01(rng)}) e.color_depth.push_back(v);
  }
  return e;
}

}  // namespace

CeilingTiming bench_blend_ceiling(engine::Context& ctx, uint32_t width, uint32_t height, uint32_t list_length,
                                  int repeats, uint32_t seed) {
  if (list_length == 0 || list_length > S4D_CEILING_MAX_LIST)
    throw std::invalid_argument("blend ceiling: list length " + std::to_string(list_length) + " is outside 1.." +
                                std::to_string(S4D_CEILING_MAX_LIST));
  CeilingTiming t{.width = width, .height = height, .list_length = list_length};
  const uint32_t tiles_x = ceil_div(width, S4D_TILE_SIZE), tiles_y = ceil_div(height, S4D_TILE_SIZE);
  t.tiles = tiles_x * tiles_y;
  const size_t pixels = size_t{width} * height;
  const Entries e = make_entries(list_length, seed);
  engine::Buffer xy = engine::buffer_from(ctx, "ceiling xy", e.xy);
  engine::Buffer conic_opacity = engine::buffer_from(ctx, "ceiling conic_opacity", e.conic_opacity);
  engine::Buffer color_depth = engine::buffer_from(ctx, "ceiling color_depth", e.color_depth);
  engine::Buffer rgb(ctx, "ceiling rgb", pixels * 12), state(ctx, "ceiling state", pixels * 16);
  engine::TimestampQueries q(ctx, 2, "ceiling timestamps");
  gpu::BlendCeilingParams p{};
  p.size = {width, height, tiles_x, tiles_y};
  p.background = {0.25f, 0.5f, 0.75f, 0.0f};
  p.list_length = list_length;
  std::vector<double> ms;
  for (int r = -1; r < repeats; ++r) {  // run -1 warms up (pipeline compilation) and is not counted
    engine::Recorder rec(ctx, "blend ceiling");
    rec.reset_queries(q);
    rec.timestamp(q, 0);
    rec.dispatch(primitives::shader_pipeline(ctx, shaders::Id::blend_ceiling),
                 {S4D_BIND(CEIL_XY, xy), S4D_BIND(CEIL_CONIC_OPACITY, conic_opacity),
                  S4D_BIND(CEIL_COLOR_DEPTH, color_depth), S4D_BIND(CEIL_RGB, rgb), S4D_BIND(CEIL_STATE, state)},
                 p, t.tiles);
    rec.timestamp(q, 1);
    ctx.run(std::move(rec));
    if (r >= 0) ms.push_back(q.elapsed_ms(0, 1));
  }
  t.gpu = summarise_ms(std::move(ms));
  t.pixel_pairs = uint64_t{t.tiles} * S4D_TILE_PIXELS * list_length;
  t.pairs_per_s = t.gpu.ms_p50 > 0 ? static_cast<double>(t.pixel_pairs) / (t.gpu.ms_p50 * 1e-3) : 0;
  const std::vector<uint32_t> s = ctx.download<uint32_t>(state, 4 * pixels);
  t.all_blended = true;
  for (size_t i = 0; i < pixels; ++i) t.all_blended = t.all_blended && s[4 * i + 2] == list_length;
  return t;
}

uint32_t ceiling_list_length(uint64_t instances, uint32_t tiles) {
  const uint64_t average = tiles == 0 ? 0 : ceil_div(instances, tiles);
  const uint64_t batches = std::max<uint64_t>(1, ceil_div(average, S4D_TILE_PIXELS));
  return static_cast<uint32_t>(std::min<uint64_t>(batches * S4D_TILE_PIXELS, S4D_CEILING_MAX_LIST));
}

}  // namespace s4d::bench
