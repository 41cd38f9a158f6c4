// Sort and scan throughput vs N on the chosen device (S4D_DEVICE to pick another). One JSON line
// per (primitive, N) on stdout; a human table on stderr. Timings come from GPU timestamps and are
// never pass/fail; each measured run is still checked against the CPU twin.
//
//   s4d_bench_primitives [--sizes 1048576,8388608] [--repeats 5] [--only sort|scan]
#include <nlohmann/json.hpp>

#include <cstdio>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "primitives_bench.h"
#include "s4d/engine/context.h"

int main(int argc, char** argv) {
  std::vector<uint32_t> sizes = {65536, 262144, 1u << 20, 1u << 22, 1u << 23};
  int repeats = 5;
  std::string only;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool has_value = i + 1 < argc;
    if (a == "--sizes" && has_value) {
      sizes.clear();
      std::stringstream ss(argv[++i]);
      for (std::string tok; std::getline(ss, tok, ',');) sizes.push_back(static_cast<uint32_t>(std::stoul(tok)));
    } else if (a == "--repeats" && has_value) {
      repeats = std::stoi(argv[++i]);
    } else if (a == "--only" && has_value) {
      only = argv[++i];
    } else {
      std::cerr << "usage: s4d_bench_primitives [--sizes N,N,...] [--repeats R] [--only sort|scan]\n";
      return a == "--help" ? 0 : 2;
    }
  }
  try {
    s4d::engine::Context ctx;
    const auto& info = ctx.info();
    std::fprintf(stderr, "device: %s (%s)\n%-15s %10s %10s %10s %14s %6s\n", info.name.c_str(), info.driver_info.c_str(),
                 "primitive", "n", "ms p50", "ms min", "keys/s", "twin");
    for (const char* which : {"sort", "scan"}) {
      if (!only.empty() && only != which) continue;
      for (uint32_t n : sizes) {
        const auto t = std::string(which) == "sort" ? s4d::bench::bench_radix_sort(ctx, n, repeats)
                                                    : s4d::bench::bench_exclusive_scan(ctx, n, repeats);
        nlohmann::json j = {{"bench", t.primitive},
                            {"variant", t.primitive == "radix_sort" ? "key32_value32" : "u32"},
                            {"device", info.name},
                            {"driver", info.driver_name + " " + info.driver_info},
                            {"n", t.n},
                            {"repeats", t.repeats},
                            {"ms_gpu_p50", t.ms_p50},
                            {"ms_gpu_min", t.ms_min},
                            {"ms_gpu_max", t.ms_max},
                            {"keys_per_s", t.keys_per_s},
                            {"matches_twin", t.matches_twin}};
        std::cout << j.dump() << std::endl;
        std::fprintf(stderr, "%-15s %10u %10.2f %10.2f %14.3g %6s\n", t.primitive.c_str(), t.n, t.ms_p50, t.ms_min,
                     t.keys_per_s, t.matches_twin ? "ok" : "WRONG");
        if (!t.matches_twin) return 1;
      }
    }
  } catch (const std::exception& e) {
    std::cerr << "s4d_bench_primitives: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
