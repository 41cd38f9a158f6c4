// "Deform only what moves" (docs/training.md, stage 2): the field runs over a prefix of the Gaussians
// (CanonicalGaussians::still_count), so the Gaussians a still mask marks are put last in memory. On
// devices that run a SIMD group's lanes together (llvmpipe, GPUs) a per-Gaussian early-out saves no
// time unless the whole group takes it, which Gaussians in arbitrary order never do.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

namespace s4d::deform {

// A stable partition: Gaussian order[j] goes to position j, the moving ones (mask 0) first, the
// still ones (mask non-zero) after them, each in their old order.
struct MotionSplit {
  std::vector<uint32_t> order;
  uint32_t still_count = 0;
  bool identity() const;  // the mask was already split: nothing moves
};
MotionSplit split_by_motion(std::span<const uint32_t> still_mask);

// The mask of `count` Gaussians whose last `still_count` are still (what checkpoints store as
// field.static_mask).
std::vector<uint32_t> tail_mask(uint32_t count, uint32_t still_count);

// Rows of `width` values in the split's order: out[j] = values[order[j]] (row by row).
template <class T>
std::vector<T> gather_rows(std::span<const T> values, std::span<const uint32_t> order, size_t width) {
  std::vector<T> out;
  out.reserve(order.size() * width);
  for (const uint32_t i : order) out.insert(out.end(), values.begin() + i * width, values.begin() + (i + 1) * width);
  return out;
}

}  // namespace s4d::deform
