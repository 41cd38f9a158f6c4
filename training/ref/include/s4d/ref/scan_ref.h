// CPU twin of the GPU exclusive scan (engine/primitives/scan.cpp): sequential, wrapping like the
// GPU for unsigned types.
#pragma once
#include <span>

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

}  // namespace s4d::ref
