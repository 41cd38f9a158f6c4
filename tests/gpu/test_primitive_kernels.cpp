// Each kernel of the scan and the radix sort on its own against its CPU twin, so a failure names
// the kernel: scan_reduce (block sums), scan_downsweep (one block, no partials), radix_count
// (per-block digit histograms), radix_scatter (one stable pass given the scanned histogram).
#include <doctest/doctest.h>

#include <cstdint>
#include <numeric>
#include <random>
#include <vector>

#include "expect_equal.h"
#include "s4d/engine/buffer.h"
#include "s4d/engine/pipeline.h"
#include "s4d/engine/recorder.h"
#include "s4d/primitives/scan.h"
#include "s4d/ref/radix_sort_ref.h"
#include "s4d/ref/scan_ref.h"
#include "s4d/shader_registry.h"
#include "s4d_primitives.h"
#include "test_context.h"

using namespace s4d;

namespace {

const engine::Pipeline& kernel(shaders::Id id) {
  const auto& e = shaders::get(id);
  return test::context().pipeline(e.name, e.spirv());
}

std::vector<uint32_t> random_u32(size_t n, uint32_t seed, uint32_t modulo = 0) {
  std::mt19937 rng(seed);
  std::vector<uint32_t> v(n);
  for (auto& x : v) x = modulo ? static_cast<uint32_t>(rng()) % modulo : static_cast<uint32_t>(rng());
  return v;
}

uint32_t blocks_of(size_t n, uint32_t block) { return static_cast<uint32_t>((n + block - 1) / block); }

}  // namespace

TEST_CASE("scan_reduce writes the sum of every block") {
  auto& ctx = test::context();
  for (uint32_t n : {1u, 1024u, 1025u, 70'000u}) {
    CAPTURE(n);
    const auto data = random_u32(n, n, 1u << 20);
    const uint32_t blocks = blocks_of(n, S4D_SCAN_BLOCK);
    engine::Buffer d(ctx, "reduce data", size_t{n} * 4), partials(ctx, "reduce partials", size_t{blocks} * 4);
    ctx.upload(d, std::span<const uint32_t>(data));
    engine::Recorder rec(ctx, "scan_reduce");
    rec.dispatch(kernel(shaders::Id::scan_reduce), {S4D_BIND(SCAN_DATA, d), S4D_BIND(SCAN_PARTIALS, partials)},
                 gpu::ScanParams{.n = n, .num_blocks = blocks}, blocks);
    ctx.run(std::move(rec));
    test::expect_equal_arrays(ctx.download<uint32_t>(partials, blocks),
                              ref::block_sums(std::span<const uint32_t>(data), S4D_SCAN_BLOCK), "block sums");
  }
}

TEST_CASE("scan_downsweep scans a single block without partials") {
  auto& ctx = test::context();
  for (uint32_t n : {1u, 300u, 1024u}) {
    CAPTURE(n);
    auto data = random_u32(n, n, 1000);
    engine::Buffer d(ctx, "downsweep data", size_t{n} * 4), unused(ctx, "unused partials", 16);
    ctx.upload(d, std::span<const uint32_t>(data));
    engine::Recorder rec(ctx, "scan_downsweep");
    rec.dispatch(kernel(shaders::Id::scan_downsweep), {S4D_BIND(SCAN_DATA, d), S4D_BIND(SCAN_PARTIALS, unused)},
                 gpu::ScanParams{.n = n, .num_blocks = 1}, 1);
    ctx.run(std::move(rec));
    ref::exclusive_scan(std::span(data));
    test::expect_equal_arrays(ctx.download<uint32_t>(d, n), data, "single-block scan");
  }
}

TEST_CASE("radix_count writes digit-major per-block histograms, with a narrow last digit too") {
  auto& ctx = test::context();
  const uint32_t n = 10'000;
  const auto keys = random_u32(n, 5);
  const uint32_t blocks = blocks_of(n, S4D_RADIX_BLOCK);
  for (auto [shift, mask] : {std::pair{0u, 15u}, std::pair{28u, 15u}, std::pair{8u, 3u}}) {
    CAPTURE(shift);
    engine::Buffer k(ctx, "count keys", size_t{n} * 4), hist(ctx, "count hist", size_t{blocks} * S4D_RADIX_BINS * 4);
    ctx.upload(k, std::span<const uint32_t>(keys));
    engine::Recorder rec(ctx, "radix_count");
    rec.dispatch(kernel(shaders::Id::radix_count), {S4D_BIND(RADIX_COUNT_KEYS, k), S4D_BIND(RADIX_COUNT_HIST, hist)},
                 gpu::RadixParams{.n = n, .shift = shift, .num_blocks = blocks, .digit_mask = mask}, blocks);
    ctx.run(std::move(rec));
    test::expect_equal_arrays(ctx.download<uint32_t>(hist, size_t{blocks} * S4D_RADIX_BINS),
                              ref::radix_block_histograms(keys, shift, mask, S4D_RADIX_BLOCK, S4D_RADIX_BINS),
                              "histograms");
  }
}

TEST_CASE("radix_scatter performs one stable pass given the scanned histogram") {
  auto& ctx = test::context();
  const uint32_t n = 9'001, shift = 4, mask = 15;
  const auto keys = random_u32(n, 9, 1u << 12);
  std::vector<uint32_t> values(n);
  std::iota(values.begin(), values.end(), 0u);
  const uint32_t blocks = blocks_of(n, S4D_RADIX_BLOCK);
  auto hist = ref::radix_block_histograms(keys, shift, mask, S4D_RADIX_BLOCK, S4D_RADIX_BINS);
  ref::exclusive_scan(std::span(hist));

  engine::Buffer k(ctx, "scatter keys", size_t{n} * 4), v(ctx, "scatter values", size_t{n} * 4);
  engine::Buffer h(ctx, "scatter hist", hist.size() * 4);
  engine::Buffer ko(ctx, "scatter keys out", size_t{n} * 4), vo(ctx, "scatter values out", size_t{n} * 4);
  ctx.upload(k, std::span<const uint32_t>(keys));
  ctx.upload(v, std::span<const uint32_t>(values));
  ctx.upload(h, std::span<const uint32_t>(hist));
  engine::Recorder rec(ctx, "radix_scatter");
  rec.dispatch(kernel(shaders::Id::radix_scatter),
               {S4D_BIND(RADIX_KEYS_IN, k), S4D_BIND(RADIX_VALUES_IN, v), S4D_BIND(RADIX_HIST, h),
                S4D_BIND(RADIX_KEYS_OUT, ko), S4D_BIND(RADIX_VALUES_OUT, vo)},
               gpu::RadixParams{.n = n, .shift = shift, .num_blocks = blocks, .digit_mask = mask}, blocks);
  ctx.run(std::move(rec));

  auto want_keys = keys;
  auto want_values = values;
  ref::radix_sort_pass(want_keys, want_values, shift, 4);
  test::expect_equal_arrays(ctx.download<uint32_t>(ko, n), want_keys, "keys after one pass");
  test::expect_equal_arrays(ctx.download<uint32_t>(vo, n), want_values, "values after one pass");
}
