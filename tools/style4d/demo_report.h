// What `style4d demo` measured, and the report it writes from it: DIR/demo.json (the numbers) and
// DIR/report.md (the same with frames, videos, the benchmark table and per-stage costs).
#pragma once
#include <nlohmann/json.hpp>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "primitives_bench.h"
#include "s4d/engine/device_info.h"

namespace s4d::cli {

// One pipeline stage: wall seconds in this process (0 when an earlier process finished it) and the
// peak of device memory its buffers held.
struct DemoStage {
  std::string name, what;
  double seconds = 0;
  uint64_t device_peak_bytes = 0;
};

struct DemoRecord {
  std::filesystem::path out;
  engine::DeviceInfo device;
  bench::PrimitiveTiming sort, scan;
  std::vector<DemoStage> stages;
  uint64_t host_peak_bytes = 0;  // the process's peak resident memory
  nlohmann::json synth, train, stylize, bench;  // each stage's own summary
  std::vector<std::string> videos;              // relative to out
  double total_seconds = 0;
  nlohmann::json time_budget;  // --time-budget: given, took, and each stage's share; null without one
};

bool engine_ok(const DemoRecord& r);
// Writes demo.json and report.md into r.out, each atomically.
void write_demo_report(const DemoRecord& r);

}  // namespace s4d::cli
