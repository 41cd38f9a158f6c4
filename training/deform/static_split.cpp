// The moving-first order of a static mask (static_split.h).
#include "s4d/deform/static_split.h"

#include <algorithm>
#include <numeric>

namespace s4d::deform {

bool StaticSplit::identity() const {
  for (uint32_t j = 0; j < order.size(); ++j)
    if (order[j] != j) return false;
  return true;
}

StaticSplit split_static(std::span<const uint32_t> static_mask) {
  StaticSplit s;
  s.order.resize(static_mask.size());
  std::iota(s.order.begin(), s.order.end(), 0u);
  const auto first_static =
      std::stable_partition(s.order.begin(), s.order.end(), [&](uint32_t i) { return static_mask[i] == 0; });
  s.static_count = static_cast<uint32_t>(s.order.end() - first_static);
  return s;
}

std::vector<uint32_t> tail_mask(uint32_t count, uint32_t static_count) {
  std::vector<uint32_t> mask(count, 0u);
  std::fill(mask.end() - static_count, mask.end(), 1u);
  return mask;
}

}  // namespace s4d::deform
