// CPU twin of shaders/viewer/present_pack.comp: the rasterizer's float RGB image, upsampled
// bilinearly when smaller than the output (pack_tap in s4d_viewer.h), quantised as io::write_png
// does and packed into one u32 per pixel. T = float follows the kernel's arithmetic; T = double is
// the exact reference.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "s4d_viewer.h"

namespace s4d::viewer {

template <typename T>
uint32_t pack_level(T v) {
  if (std::isnan(v)) return 0;
  return static_cast<uint32_t>(std::floor(std::clamp(v, T(0), T(1)) * T(255) + T(0.5)));
}

// rgb: [src_height * src_width * 3]; returns [height * width] pixels, bytes R, G, B, 255 (B, G, R,
// 255 with swap_rb). Throws std::invalid_argument when the source is larger than the output or
// rgb has the wrong size.
template <typename T>
std::vector<uint32_t> present_pack_ref(const std::vector<T>& rgb, uint32_t src_width, uint32_t src_height,
                                       uint32_t width, uint32_t height, bool swap_rb) {
  if (src_width == 0 || src_height == 0 || src_width > width || src_height > height)
    throw std::invalid_argument("present_pack: source " + std::to_string(src_width) + "x" +
                                std::to_string(src_height) + " must be non-empty and fit the output " +
                                std::to_string(width) + "x" + std::to_string(height));
  if (rgb.size() != size_t{src_width} * src_height * 3)
    throw std::invalid_argument("present_pack: rgb has " + std::to_string(rgb.size()) + " floats, expected " +
                                std::to_string(size_t{src_width} * src_height * 3));
  auto texel = [&](uint32_t x, uint32_t y) {
    const size_t i = 3 * (size_t{y} * src_width + x);
    return std::array<T, 3>{rgb[i], rgb[i + 1], rgb[i + 2]};
  };
  auto mix = [](const std::array<T, 3>& a, const std::array<T, 3>& b, T t) {
    std::array<T, 3> c;
    for (int k = 0; k < 3; ++k) c[k] = a[k] * (T(1) - t) + b[k] * t;
    return c;
  };
  auto row_sample = [&](gpu::PackTap tx, uint32_t y) {
    const std::array<T, 3> a = texel(tx.i0, y);
    if (tx.num == 0) return a;
    return mix(a, texel(tx.i0 + 1, y), static_cast<T>(tx.num) / static_cast<T>(2 * width));
  };
  std::vector<uint32_t> pixels(size_t{width} * height);
  for (uint32_t y = 0; y < height; ++y) {
    const gpu::PackTap ty = gpu::pack_tap(y, src_height, height);
    for (uint32_t x = 0; x < width; ++x) {
      const gpu::PackTap tx = gpu::pack_tap(x, src_width, width);
      std::array<T, 3> c = row_sample(tx, ty.i0);
      if (ty.num != 0) c = mix(c, row_sample(tx, ty.i0 + 1), static_cast<T>(ty.num) / static_cast<T>(2 * height));
      uint32_t r = pack_level(c[0]), g = pack_level(c[1]), b = pack_level(c[2]);
      if (swap_rb) std::swap(r, b);
      pixels[size_t{y} * width + x] = r | (g << 8) | (b << 16) | (255u << 24);
    }
  }
  return pixels;
}

}  // namespace s4d::viewer
