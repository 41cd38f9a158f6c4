// GPU exclusive scan against its CPU twin at every size the engine contract lists, including
// sizes around the block size and the multi-level recursion (3,000,000 needs three levels).
#include <doctest/doctest.h>

#include <cstdint>
#include <random>
#include <vector>

#include "expect_equal.h"
#include "s4d/primitives/scan.h"
#include "s4d/ref/scan_ref.h"
#include "s4d_primitives.h"
#include "test_context.h"

using namespace s4d;

namespace {

std::vector<uint32_t> gpu_scan(const std::vector<uint32_t>& input) {
  auto& ctx = test::context();
  const uint32_t n = static_cast<uint32_t>(input.size());
  engine::Buffer data(ctx, "scan data", input.size() * 4);
  engine::Buffer scratch(ctx, "scan scratch", primitives::scan_scratch_bytes(n));
  ctx.upload(data, std::span<const uint32_t>(input));
  engine::Recorder rec(ctx, "scan");
  primitives::cmd_exclusive_scan(rec, data, n, scratch);
  ctx.run(std::move(rec));
  return ctx.download<uint32_t>(data, n);
}

void check_scan(const std::vector<uint32_t>& input, const char* what) {
  std::vector<uint32_t> want = input;
  ref::exclusive_scan(std::span(want));
  test::expect_equal_arrays(gpu_scan(input), want, what);
}

}  // namespace

TEST_CASE("scan matches the twin at every listed size") {
  std::mt19937 rng(7);
  for (uint32_t n : {0u, 1u, 7u, 255u, 256u, 257u, 1023u, 1024u, 1025u, 65537u, 1u << 20, 3'000'000u}) {
    CAPTURE(n);
    std::vector<uint32_t> v(n);
    for (auto& x : v) x = static_cast<uint32_t>(rng()) % 1000;
    check_scan(v, "random values");
  }
}

TEST_CASE("scan wraps modulo 2^32 like the twin when values have all bits set") {
  for (uint32_t n : {257u, 65537u}) {
    CAPTURE(n);
    check_scan(std::vector<uint32_t>(n, 0xffffffffu), "all bits set");
  }
}

TEST_CASE("scan scratch size covers every level") {
  CHECK(primitives::scan_scratch_bytes(0) == 0);
  CHECK(primitives::scan_scratch_bytes(S4D_SCAN_BLOCK) == 0);
  // Each level of block sums is padded to 64 words so every level's offset is 256-byte aligned.
  CHECK(primitives::scan_scratch_bytes(S4D_SCAN_BLOCK + 1) == 64 * 4);
  // 3,000,000 -> 2,930 block sums (padded to 2,944) -> 3 block sums (padded to 64).
  CHECK(primitives::scan_scratch_bytes(3'000'000) == (2944 + 64) * 4);
}
