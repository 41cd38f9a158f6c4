#include "primitives_bench.h"

#include <algorithm>
#include <numeric>
#include <random>
#include <stdexcept>
#include <vector>

#include "s4d/engine/buffer.h"
#include "s4d/engine/recorder.h"
#include "s4d/engine/timestamps.h"
#include "s4d/primitives/iota.h"
#include "s4d/primitives/radix_sort.h"
#include "s4d/primitives/scan.h"

namespace s4d::bench {

namespace {

std::vector<uint32_t> random_u32(uint32_t n, uint32_t seed, uint32_t modulo = 0) {
  std::mt19937 rng(seed);
  std::vector<uint32_t> v(n);
  for (auto& x : v) x = modulo ? static_cast<uint32_t>(rng()) % modulo : static_cast<uint32_t>(rng());
  return v;
}

void summarise(PrimitiveTiming& t, std::vector<double> ms) {
  if (ms.empty()) throw std::invalid_argument("benchmark needs at least one repeat");
  std::sort(ms.begin(), ms.end());
  t.repeats = static_cast<int>(ms.size());
  t.ms_min = ms.front();
  t.ms_max = ms.back();
  t.ms_p50 = ms[ms.size() / 2];
  t.keys_per_s = t.ms_p50 > 0 ? t.n / (t.ms_p50 * 1e-3) : 0;
}

}  // namespace

PrimitiveTiming bench_radix_sort(engine::Context& ctx, uint32_t n, int repeats, uint32_t seed) {
  PrimitiveTiming t{.primitive = "radix_sort", .n = n};
  const std::vector<uint32_t> keys = random_u32(n, seed);
  engine::Buffer k(ctx, "bench sort keys", size_t{n} * 4), v(ctx, "bench sort values", size_t{n} * 4);
  primitives::RadixSortScratch scratch(ctx, n, "bench sort");
  engine::TimestampQueries q(ctx, 2, "bench sort timestamps");
  std::vector<double> ms;
  for (int r = -1; r < repeats; ++r) {  // run -1 warms up (pipeline compilation) and is not counted
    ctx.upload(k, std::span<const uint32_t>(keys));
    engine::Recorder rec(ctx, "bench sort");
    primitives::cmd_iota(rec, v, n);
    rec.barrier();
    rec.reset_queries(q);
    rec.timestamp(q, 0);
    primitives::cmd_radix_sort(rec, k, v, n, 32, scratch);
    rec.timestamp(q, 1);
    ctx.run(std::move(rec));
    if (r >= 0) ms.push_back(q.elapsed_ms(0, 1));
  }
  // A radix sort is stable: the values (the keys' first positions) come out in order of key, then position.
  std::vector<uint32_t> want_values(n), want_keys(n);
  std::iota(want_values.begin(), want_values.end(), 0u);
  std::stable_sort(want_values.begin(), want_values.end(), [&](uint32_t a, uint32_t b) { return keys[a] < keys[b]; });
  for (uint32_t i = 0; i < n; ++i) want_keys[i] = keys[want_values[i]];
  t.matches_twin = ctx.download<uint32_t>(k, n) == want_keys && ctx.download<uint32_t>(v, n) == want_values;
  summarise(t, ms);
  return t;
}

PrimitiveTiming bench_exclusive_scan(engine::Context& ctx, uint32_t n, int repeats, uint32_t seed) {
  PrimitiveTiming t{.primitive = "exclusive_scan", .n = n};
  const std::vector<uint32_t> input = random_u32(n, seed, 1000);
  engine::Buffer data(ctx, "bench scan data", size_t{n} * 4);
  engine::Buffer scratch(ctx, "bench scan scratch", primitives::scan_scratch_bytes(n));
  engine::TimestampQueries q(ctx, 2, "bench scan timestamps");
  std::vector<double> ms;
  for (int r = -1; r < repeats; ++r) {  // run -1 warms up (pipeline compilation) and is not counted
    ctx.upload(data, std::span<const uint32_t>(input));
    engine::Recorder rec(ctx, "bench scan");
    rec.reset_queries(q);
    rec.timestamp(q, 0);
    primitives::cmd_exclusive_scan(rec, data, n, scratch);
    rec.timestamp(q, 1);
    ctx.run(std::move(rec));
    if (r >= 0) ms.push_back(q.elapsed_ms(0, 1));
  }
  std::vector<uint32_t> want(n);
  std::exclusive_scan(input.begin(), input.end(), want.begin(), 0u);  // unsigned: wraps as the GPU's does
  t.matches_twin = ctx.download<uint32_t>(data, n) == want;
  summarise(t, ms);
  return t;
}

}  // namespace s4d::bench
