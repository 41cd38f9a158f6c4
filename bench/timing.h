// Summary of repeated timings: median (the upper one for an even count), minimum and maximum.
#pragma once
#include <algorithm>
#include <stdexcept>
#include <vector>

namespace s4d::bench {

struct Timing {
  int repeats = 0;
  double ms_p50 = 0, ms_min = 0, ms_max = 0;
};

inline Timing summarise_ms(std::vector<double> ms) {
  if (ms.empty()) throw std::invalid_argument("benchmark needs at least one repeat");
  std::sort(ms.begin(), ms.end());
  return {.repeats = static_cast<int>(ms.size()),
          .ms_p50 = ms[ms.size() / 2],
          .ms_min = ms.front(),
          .ms_max = ms.back()};
}

}  // namespace s4d::bench
