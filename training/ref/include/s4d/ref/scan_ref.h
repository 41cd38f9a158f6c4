// CPU twin of the GPU exclusive scan (engine/primitives/scan.cpp): sequential, wrapping like the
// GPU for unsigned types.
#pragma once
#include <span>
#include <vector>

namespace s4d::ref {

template <class T>
void exclusive_scan(std::span<T> data) {
  T running{};
  for (T& x : data) {
    const T v = x;
    x = running;
    running = static_cast<T>(running + v);
  }
}

// Twin of scan_reduce: the sum of each block of `block` elements (the last block may be short).
template <class T>
std::vector<T> block_sums(std::span<const T> data, size_t block) {
  std::vector<T> sums((data.size() + block - 1) / block, T{});
  for (size_t i = 0; i < data.size(); ++i) sums[i / block] = static_cast<T>(sums[i / block] + data[i]);
  return sums;
}

}  // namespace s4d::ref
