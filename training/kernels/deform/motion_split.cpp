// The moving-first order of a still mask (motion_split.h).
#include "s4d/deform/motion_split.h"

#include <algorithm>
#include <numeric>

namespace s4d::deform {

bool MotionSplit::identity() const {
  for (uint32_t j = 0; j < order.size(); ++j)
    if (order[j] != j) return false;
  return true;
}

MotionSplit split_by_motion(std::span<const uint32_t> still_mask) {
  MotionSplit s;
  s.order.resize(still_mask.size());
  std::iota(s.order.begin(), s.order.end(), 0u);
  const auto first_still =
      std::stable_partition(s.order.begin(), s.order.end(), [&](uint32_t i) { return still_mask[i] == 0; });
  s.still_count = static_cast<uint32_t>(s.order.end() - first_still);
  return s;
}

std::vector<uint32_t> tail_mask(uint32_t count, uint32_t still_count) {
  std::vector<uint32_t> mask(count, 0u);
  std::fill(mask.end() - still_count, mask.end(), 1u);
  return mask;
}

}  // namespace s4d::deform
