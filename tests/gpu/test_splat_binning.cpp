// The rasterizer's binning kernels one by one against their twins (splat_binning_ref.h):
// count_tiles (including the carry past 2^32 instances), emit_instances, tile_ranges,
// tile_list_stats; and the twins chained reproduce ref::tile_lists.
#include <doctest/doctest.h>

#include <algorithm>
#include <numeric>
#include <random>
#include <span>
#include <vector>

#include "expect_equal.h"
#include "s4d/engine/buffer_from.h"
#include "s4d/engine/recorder.h"
#include "s4d/primitives/shader_pipeline.h"
#include "s4d/ref/scan_ref.h"
#include "s4d/ref/splat_binning_ref.h"
#include "splat_harness.h"
#include "s4d_splat.h"
#include "test_context.h"

namespace {

using namespace s4d;

// mt19937's results are 32-bit values in a wider type.
uint32_t draw(std::mt19937& rng, uint32_t bound) { return static_cast<uint32_t>(rng() % bound); }

uint32_t groups(size_t n) { return static_cast<uint32_t>((n + S4D_SPLAT_WG - 1) / S4D_SPLAT_WG); }

std::vector<uint32_t> permutation(size_t n, std::mt19937& rng) {
  std::vector<uint32_t> p(n);
  std::iota(p.begin(), p.end(), 0u);
  std::shuffle(p.begin(), p.end(), rng);
  return p;
}

// Random tile rectangles (a quarter of them empty) on a tiles_x x tiles_y grid, as project_fwd packs them.
std::vector<uint32_t> random_info(size_t n, uint32_t tiles_x, uint32_t tiles_y, std::mt19937& rng) {
  std::vector<uint32_t> info(4 * n, 0);
  for (size_t g = 0; g < n; ++g) {
    if (draw(rng, 4) == 0) continue;
    const uint32_t x0 = draw(rng, tiles_x), y0 = draw(rng, tiles_y);
    const uint32_t x1 = x0 + 1 + draw(rng, tiles_x - x0), y1 = y0 + 1 + draw(rng, tiles_y - y0);
    info[4 * g] = x0 | y0 << 16, info[4 * g + 1] = x1 | y1 << 16, info[4 * g + 2] = 3;
  }
  return info;
}

uint32_t area(const std::vector<uint32_t>& info, size_t g) {
  return ((info[4 * g + 1] & 0xFFFFu) - (info[4 * g] & 0xFFFFu)) * ((info[4 * g + 1] >> 16) - (info[4 * g] >> 16));
}

// count_tiles' twin followed by the scan's: each Gaussian's first instance slot.
std::vector<uint32_t> scanned_offsets(const std::vector<uint32_t>& ids, const std::vector<uint32_t>& touched) {
  std::vector<uint32_t> offsets = ref::count_tiles(ids, touched).offsets;
  ref::exclusive_scan(std::span<uint32_t>(offsets));
  return offsets;
}

}  // namespace

TEST_CASE("count_tiles gathers tiles touched in depth order and counts instances with carries") {
  std::mt19937 rng(1);
  const size_t n = 3000;
  const std::vector<uint32_t> ids = permutation(n, rng);
  for (const bool huge : {false, true}) {
    CAPTURE(huge);
    std::vector<uint32_t> touched(n);
    // huge: areas near 2^31 so the u32 total wraps many times (the host refuses those views).
    for (uint32_t& t : touched) t = draw(rng, 5) == 0 ? 0u : (huge ? 0x7FFF0000u + draw(rng, 1000) : 1 + draw(rng, 40));
    engine::Buffer bids = engine::buffer_from(test::context(), "ids", ids), btouched = engine::buffer_from(test::context(), "touched", touched);
    engine::Buffer offsets = engine::buffer_from(test::context(), "offsets", std::vector<uint32_t>(n + 1, 7)), totals = engine::buffer_from(test::context(), "totals", std::vector<uint32_t>{0, 0, 0});
    engine::Recorder rec(test::context(), "count_tiles");
    rec.dispatch(primitives::shader_pipeline(test::context(), shaders::Id::count_tiles),
                 {S4D_BIND(COUNT_SORTED_IDS, bids), S4D_BIND(COUNT_TILES_TOUCHED, btouched),
                  S4D_BIND(COUNT_OFFSETS, offsets), S4D_BIND(COUNT_TOTALS, totals)},
                 gpu::BinningParams{.n = static_cast<uint32_t>(n), .tiles_x = 1, .capacity = 0, ._pad1 = 0},
                 groups(n + 1));
    test::context().run(std::move(rec));
    const ref::CountTiles want = ref::count_tiles(ids, touched);
    test::expect_equal_arrays(test::context().download<uint32_t>(offsets, n + 1), want.offsets, "offsets");
    const auto got = test::context().download<uint32_t>(totals, 3);
    CHECK(got[0] == want.instances_low);
    CHECK(got[1] == want.carries);
    CHECK(got[2] == want.largest);
    CHECK((want.carries > 0) == huge);
  }
}

TEST_CASE("emit_instances, tile_ranges and tile_list_stats match their twins exactly") {
  std::mt19937 rng(2);
  const size_t n = 2000;
  const uint32_t tiles_x = 7, tiles_y = 5, tiles = tiles_x * tiles_y;
  const std::vector<uint32_t> ids = permutation(n, rng), info = random_info(n, tiles_x, tiles_y, rng);
  std::vector<uint32_t> touched(n);
  for (size_t g = 0; g < n; ++g) touched[g] = area(info, g);
  const std::vector<uint32_t> offsets = scanned_offsets(ids, touched);
  const uint32_t instances = offsets.back();

  engine::Context& ctx = test::context();
  engine::Buffer bids = engine::buffer_from(test::context(), "ids", ids), boffsets = engine::buffer_from(test::context(), "offsets", offsets), binfo = engine::buffer_from(test::context(), "info", info);
  engine::Buffer keys = engine::buffer_from(test::context(), "keys", std::vector<uint32_t>(instances, 0xDEAD));
  engine::Buffer values = engine::buffer_from(test::context(), "values", std::vector<uint32_t>(instances, 0xDEAD));
  // capacity: every instance, then a third of them (the rasterizer's overflow path drops the rest).
  const auto emit = [&](uint32_t capacity) {
    engine::Recorder rec(ctx, "emit_instances");
    rec.fill(keys, 0xDEAD);
    rec.fill(values, 0xDEAD);
    rec.barrier();
    rec.dispatch(primitives::shader_pipeline(ctx, shaders::Id::emit_instances),
                 {S4D_BIND(EMIT_SORTED_IDS, bids), S4D_BIND(EMIT_OFFSETS, boffsets), S4D_BIND(EMIT_INFO, binfo),
                  S4D_BIND(EMIT_TILE_KEYS, keys), S4D_BIND(EMIT_GAUSSIAN_IDS, values)},
                 gpu::BinningParams{.n = static_cast<uint32_t>(n), .tiles_x = tiles_x, .capacity = capacity, ._pad1 = 0},
                 groups(n));
    ctx.run(std::move(rec));
  };
  const uint32_t third = instances / 3;
  emit(third);
  const auto capped_keys = ctx.download<uint32_t>(keys, instances);
  emit(instances);
  const ref::Instances want = ref::emit_instances(ids, offsets, info, tiles_x);
  test::expect_equal_arrays(ctx.download<uint32_t>(keys, instances), want.tile_keys, "tile keys");
  test::expect_equal_arrays(ctx.download<uint32_t>(values, instances), want.gaussian_ids, "Gaussian ids");
  std::vector<uint32_t> want_capped(want.tile_keys.begin(), want.tile_keys.begin() + third);
  want_capped.resize(instances, 0xDEAD);
  test::expect_equal_arrays(capped_keys, want_capped, "tile keys below a capacity of a third");

  // tile_ranges over keys sorted stably by tile (the engine's radix sort is tested on its own).
  std::vector<uint32_t> order(instances);
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return want.tile_keys[a] < want.tile_keys[b]; });
  std::vector<uint32_t> sorted_keys(instances);
  for (size_t i = 0; i < instances; ++i) sorted_keys[i] = want.tile_keys[order[i]];
  sorted_keys.erase(std::remove(sorted_keys.begin(), sorted_keys.end(), 11u), sorted_keys.end());  // one empty tile
  engine::Buffer bsorted = engine::buffer_from(test::context(), "sorted keys", sorted_keys), ranges = engine::buffer_from(test::context(), "ranges", std::vector<uint32_t>(2 * tiles, 0));
  engine::Buffer longest = engine::buffer_from(test::context(), "longest", std::vector<uint32_t>{0});
  const uint32_t m = static_cast<uint32_t>(sorted_keys.size());
  // The live count comes from the device (InstanceArgs::live); the push constant is only its bound.
  engine::Buffer live = engine::buffer_from(ctx, "live", std::vector<uint32_t>{m, 0, 0, 0});
  engine::Recorder rec2(ctx, "tile_ranges");
  rec2.dispatch(primitives::shader_pipeline(ctx, shaders::Id::tile_ranges),
                {S4D_BIND(RANGES_TILE_KEYS, bsorted), S4D_BIND(RANGES_OUT, ranges), S4D_BIND(RANGES_LIVE, live)},
                gpu::BinningParams{.n = m + 300, .tiles_x = tiles_x, .capacity = 0, ._pad1 = 0}, groups(m + 300));
  rec2.barrier();
  rec2.dispatch(primitives::shader_pipeline(ctx, shaders::Id::tile_list_stats),
                {S4D_BIND(LIST_STATS_RANGES, ranges), S4D_BIND(LIST_STATS_OUT, longest)},
                gpu::BinningParams{.n = tiles, .tiles_x = tiles_x, .capacity = 0, ._pad1 = 0}, groups(tiles));
  ctx.run(std::move(rec2));
  const std::vector<uint32_t> want_ranges = ref::tile_ranges(sorted_keys, tiles);
  test::expect_equal_arrays(ctx.download<uint32_t>(ranges, 2 * tiles), want_ranges, "tile ranges");
  CHECK(ctx.download<uint32_t>(longest, 1)[0] == ref::longest_tile_list(want_ranges));
  CHECK(want_ranges[2 * 11] == 0);
  CHECK(want_ranges[2 * 11 + 1] == 0);
}

TEST_CASE("the binning twins chained give the twin's tile lists") {
  std::mt19937 rng(3);
  const test::Cam cam = test::random_camera(70, 45, rng);
  const test::Scene g = test::random_scene(400, 0, false, rng);
  const ref::Projected<float> p = ref::project_fwd(g, cam);
  const size_t n = g.size();
  std::vector<uint32_t> ids(n), touched(n), info(4 * n, 0);
  std::iota(ids.begin(), ids.end(), 0u);
  std::stable_sort(ids.begin(), ids.end(), [&](uint32_t a, uint32_t b) { return p.depth[a] < p.depth[b]; });
  for (size_t i = 0; i < n; ++i) {
    const int* r = &p.tile_rect[4 * i];
    if (p.radius[i] == 0) continue;
    info[4 * i] = static_cast<uint32_t>(r[0] | r[1] << 16), info[4 * i + 1] = static_cast<uint32_t>(r[2] | r[3] << 16);
    touched[i] = static_cast<uint32_t>((r[2] - r[0]) * (r[3] - r[1]));
  }
  const std::vector<uint32_t> offsets = scanned_offsets(ids, touched);
  const ref::Instances inst = ref::emit_instances(ids, offsets, info, static_cast<uint32_t>(cam.tiles_x()));
  const auto lists = ref::tile_lists(p, cam);
  std::vector<std::vector<int>> chained(lists.size());
  for (size_t i = 0; i < inst.tile_keys.size(); ++i)  // emitted in depth order: appending keeps it per tile
    chained[inst.tile_keys[i]].push_back(static_cast<int>(inst.gaussian_ids[i]));
  CHECK(chained == lists);
}
