// The blend_ceiling benchmark kernel against the twin's blending: every tile blends the same list
// with tile-local means, so each tile must equal ref::raster_fwd of one 16x16 tile over that list.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "s4d/engine/buffer_from.h"
#include "s4d/engine/buffer.h"
#include "s4d/engine/recorder.h"
#include "s4d/primitives/shader_pipeline.h"
#include "s4d/ref/splat_raster_ref.h"
#include "s4d_bench.h"
#include "s4d_splat.h"
#include "test_context.h"

using namespace s4d;

TEST_CASE("blend_ceiling blends every tile like the twin blends one tile") {
  // 300 entries in increasing depth (the twin orders by depth), alphas from skipped to capped, so
  // skips, the 0.99 cap and early termination all occur; two batches of 256.
  const uint32_t L = 300, width = 40, height = 20;  // 3 x 2 tiles, the last column partial
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-1, 1), u01(0, 1);
  ref::Projected<float> p;
  std::vector<float> xy, co, cd;
  for (uint32_t i = 0; i < L; ++i) {
    const float x = 16 * u01(rng), y = 16 * u01(rng), a = 0.02f + 0.1f * u01(rng), c = 0.02f + 0.1f * u01(rng);
    const float b = 0.01f * u(rng), o = u01(rng), depth = 1.0f + 0.01f * static_cast<float>(i);
    const float r = u01(rng), g = u01(rng), bl = u01(rng);
    for (float v : {x, y}) xy.push_back(v), p.mean2d.push_back(v);
    for (float v : {a, b, c, o}) co.push_back(v);
    for (float v : {r, g, bl, depth}) cd.push_back(v);
    for (float v : {a, b, c}) p.conic.push_back(v);
    for (float v : {r, g, bl}) p.rgb.push_back(v);
    p.opacity.push_back(o), p.depth.push_back(depth), p.radius.push_back(8);
    for (int v : {0, 0, 1, 1}) p.tile_rect.push_back(v);
  }
  ref::Camera<float> tile;
  tile.width = tile.height = S4D_TILE_SIZE;
  const std::array<float, 3> bg = {0.25f, 0.5f, 0.75f};
  const ref::Image<float> want = ref::raster_fwd(p, tile, bg);

  engine::Context& ctx = test::context();
  engine::Buffer bxy = engine::buffer_from(test::context(), "xy", xy), bco = engine::buffer_from(test::context(), "conic_opacity", co), bcd = engine::buffer_from(test::context(), "color_depth", cd);
  engine::Buffer rgb(ctx, "rgb", size_t{width} * height * 12), state(ctx, "state", size_t{width} * height * 16);
  gpu::BlendCeilingParams params{};
  params.size = {width, height, 3, 2};
  params.background = {bg[0], bg[1], bg[2], 0.0f};
  params.list_length = L;
  engine::Recorder rec(ctx, "blend_ceiling");
  rec.dispatch(primitives::shader_pipeline(ctx, shaders::Id::blend_ceiling),
               {S4D_BIND(CEIL_XY, bxy), S4D_BIND(CEIL_CONIC_OPACITY, bco), S4D_BIND(CEIL_COLOR_DEPTH, bcd),
                S4D_BIND(CEIL_RGB, rgb), S4D_BIND(CEIL_STATE, state)},
               params, 6);
  ctx.run(std::move(rec));
  const auto got_rgb = ctx.download<float>(rgb, size_t{width} * height * 3);
  const auto got_state = ctx.download<uint32_t>(state, size_t{width} * height * 4);

  double worst = 0;
  size_t count_mismatch = 0;
  for (uint32_t y = 0; y < height; ++y)
    for (uint32_t x = 0; x < width; ++x) {
      const size_t o = size_t{y} * width + x, t = size_t{y % 16} * 16 + x % 16;
      for (size_t ch = 0; ch < 3; ++ch) worst = std::max(worst, std::abs(double(got_rgb[3 * o + ch]) - want.rgb[3 * t + ch]));
      float T = 0;
      std::memcpy(&T, &got_state[4 * o], 4);
      worst = std::max(worst, std::abs(double(T) - (1 - want.alpha[t])));
      count_mismatch += got_state[4 * o + 2] != static_cast<uint32_t>(want.count[t]);
      count_mismatch += got_state[4 * o + 3] != static_cast<uint32_t>(want.last[t]);
    }
  CHECK(worst <= 1e-5);  // the same float blend in both; measured 1.8e-7
  CHECK(count_mismatch == 0);
  CHECK(*std::max_element(want.count.begin(), want.count.end()) < static_cast<int>(L));  // some pixels stop early
}
