// GPU radix sort against its CPU twin: every listed size, random keys, keys with all bits set,
// already sorted and reversed input, heavy ties (stability), and partial-width keys.
#include <doctest/doctest.h>

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <random>
#include <stdexcept>
#include <vector>

#include "expect_equal.h"
#include "s4d/primitives/iota.h"
#include "s4d/engine/buffer_from.h"
#include "s4d/primitives/radix_sort.h"
#include "s4d_primitives.h"
#include "s4d/ref/radix_sort_ref.h"
#include "test_context.h"

using namespace s4d;

namespace {

// Sorts (keys, iota) on the GPU and compares keys and values with the twin.
void check_sort(const std::vector<uint32_t>& keys, uint32_t key_bits, const char* what) {
  auto& ctx = test::context();
  const uint32_t n = static_cast<uint32_t>(keys.size());
  engine::Buffer k(ctx, "sort keys", keys.size() * 4), v(ctx, "sort values", keys.size() * 4);
  primitives::RadixSortScratch scratch(ctx, n, "sort test");
  ctx.upload(k, std::span<const uint32_t>(keys));
  engine::Recorder rec(ctx, "sort");
  primitives::cmd_iota(rec, v, n);
  rec.barrier();
  primitives::cmd_radix_sort(rec, k, v, n, key_bits, scratch);
  ctx.run(std::move(rec));

  std::vector<uint32_t> want_keys = keys, want_values(n);
  std::iota(want_values.begin(), want_values.end(), 0u);
  if (n > 0) ref::radix_sort(want_keys, want_values, key_bits);
  test::expect_equal_arrays(ctx.download<uint32_t>(k, n), want_keys, what);
  test::expect_equal_arrays(ctx.download<uint32_t>(v, n), want_values, what);
}

std::vector<uint32_t> random_keys(uint32_t n, uint32_t seed) {
  std::mt19937 rng(seed);
  std::vector<uint32_t> keys(n);
  for (auto& x : keys) x = static_cast<uint32_t>(rng());
  return keys;
}

}  // namespace

TEST_CASE("radix sort matches the twin on random keys at every listed size") {
  for (uint32_t n : {0u, 1u, 7u, 255u, 256u, 257u, 65537u, 1u << 20, 3'000'000u}) {
    CAPTURE(n);
    check_sort(random_keys(n, n + 1), 32, "random keys");
  }
}

TEST_CASE("radix sort handles keys with all bits set, sorted and reversed input") {
  for (uint32_t n : {7u, 257u, 65537u, 3'000'000u}) {
    CAPTURE(n);
    check_sort(std::vector<uint32_t>(n, 0xffffffffu), 32, "all bits set");
    std::vector<uint32_t> sorted = random_keys(n, 3);
    std::sort(sorted.begin(), sorted.end());
    check_sort(sorted, 32, "already sorted");
    std::reverse(sorted.begin(), sorted.end());
    check_sort(sorted, 32, "reversed");
  }
}

TEST_CASE("radix sort is stable under heavy ties") {
  std::vector<uint32_t> keys = random_keys(100'000, 11);
  for (auto& k : keys) k %= 3;  // three distinct keys: values must stay in input order per key
  check_sort(keys, 32, "three distinct keys");
}

TEST_CASE("radix sort on the low bits only orders by those bits, stably") {
  for (uint32_t bits : {1u, 5u, 12u}) {
    CAPTURE(bits);
    check_sort(random_keys(70'000, bits), bits, "partial-width keys");
  }
}

TEST_CASE("radix sort refuses more pairs than its scratch holds") {
  auto& ctx = test::context();
  engine::Buffer k(ctx, "k", 400), v(ctx, "v", 400);
  primitives::RadixSortScratch scratch(ctx, 50, "small");
  engine::Recorder rec(ctx, "too many");
  CHECK_THROWS_WITH_AS(primitives::cmd_radix_sort(rec, k, v, 100, 32, scratch), doctest::Contains("capacity"),
                       std::invalid_argument);
  CHECK_THROWS_WITH_AS(primitives::cmd_radix_sort(rec, k, v, 10, 0, scratch), doctest::Contains("key_bits"),
                       std::invalid_argument);
}

// The live form: the count comes from the device and only its blocks run; the pairs are those of
// a sort of exactly that many, bit for bit, whatever the bound (the buffers' size) beyond it.
TEST_CASE("radix sort of a device-side live count matches the sort of that many pairs") {
  auto& ctx = test::context();
  const uint32_t bound = 3 * S4D_RADIX_BLOCK + 100;
  const std::vector<uint32_t> keys = random_keys(bound, 41);
  for (const uint32_t live : {0u, 1u, 5u, uint32_t{S4D_RADIX_BLOCK}, uint32_t{S4D_RADIX_BLOCK} + 1, bound - 7, bound,
                              bound + 500}) {
    CAPTURE(live);
    const uint32_t n = std::min(live, bound);
    engine::Buffer k(ctx, "live keys", size_t{bound} * 4), v(ctx, "live values", size_t{bound} * 4);
    ctx.upload(k, std::span<const uint32_t>(keys));
    primitives::RadixSortScratch scratch(ctx, bound, "live sort");
    engine::Recorder rec(ctx, "live sort");
    const engine::Groups g = rec.split_groups((n + S4D_RADIX_BLOCK - 1) / S4D_RADIX_BLOCK);
    engine::Buffer count = engine::buffer_from(ctx, "live count", std::vector<uint32_t>{live, 0, 0, 0, g.x, g.y, g.z, 0});
    primitives::cmd_iota(rec, v, bound);
    rec.barrier();
    primitives::cmd_radix_sort(rec, k, v, primitives::LiveCount{.count = count, .groups = count, .groups_offset = 16,
                                                                 .bound = bound},
                               13, scratch);
    ctx.run(std::move(rec));
    std::vector<uint32_t> want_keys(keys.begin(), keys.begin() + n), want_values(n);
    std::iota(want_values.begin(), want_values.end(), 0u);
    if (n > 0) ref::radix_sort(want_keys, want_values, 13);
    test::expect_equal_arrays(ctx.download<uint32_t>(k, n), want_keys, "live keys");
    test::expect_equal_arrays(ctx.download<uint32_t>(v, n), want_values, "live values");
  }
}
