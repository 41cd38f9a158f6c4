// A host image of any channel count, [C, H, W] row-major: the layout of nn::Tensor on the device,
// the CPU twins' images (training/ref nn_ref.h) and the learned metrics' features alike.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

namespace s4d::util {

template <class T>
struct Chw {
  uint32_t c = 0, h = 0, w = 0;
  std::vector<T> v;  // [c, h, w]

  Chw() = default;
  Chw(uint32_t channels, uint32_t height, uint32_t width)
      : c(channels), h(height), w(width), v(size_t{channels} * height * width, T(0)) {}
  T& at(uint32_t ch, uint32_t y, uint32_t x) { return v[(size_t{ch} * h + y) * w + x]; }
  const T& at(uint32_t ch, uint32_t y, uint32_t x) const { return v[(size_t{ch} * h + y) * w + x]; }
};

}  // namespace s4d::util
