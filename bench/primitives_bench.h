// Throughput measurement of the GPU primitives (radix sort, exclusive scan) with GPU timestamps,
// each result checked against the standard library's (std::stable_sort, std::exclusive_scan) on the
// CPU; the twins (training/ref) stay with the tests. Shared by the bench executable and `style4d demo`.
#pragma once
#include <cstdint>
#include <string>

#include "s4d/engine/context.h"

namespace s4d::bench {

struct PrimitiveTiming {
  std::string primitive;  // "radix_sort" (32-bit keys + 32-bit values) or "exclusive_scan" (u32)
  uint32_t n = 0;
  int repeats = 0;
  double ms_p50 = 0, ms_min = 0, ms_max = 0;  // GPU time from timestamps
  double keys_per_s = 0;                      // n / p50
  bool matches_twin = false;                  // the GPU result equals the CPU's
};

PrimitiveTiming bench_radix_sort(engine::Context& ctx, uint32_t n, int repeats, uint32_t seed = 1);
PrimitiveTiming bench_exclusive_scan(engine::Context& ctx, uint32_t n, int repeats, uint32_t seed = 1);

}  // namespace s4d::bench
