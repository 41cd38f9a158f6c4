#include "study_media.h"

#include <algorithm>

namespace s4d::study {

namespace {

uint64_t splitmix(uint64_t& state) {
  uint64_t z = (state += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

}  // namespace

void corrupt_frame(io::ImageF& im, int index, uint64_t seed) {
  uint64_t state = seed * 1000003u + static_cast<uint64_t>(index);
  const int block = std::max(2, std::min(im.width, im.height) / 6);
  const bool invert = (index / 8) % 2 == 1;
  for (int by = 0; by < im.height; by += block)
    for (int bx = 0; bx < im.width; bx += block) {
      const uint64_t r = splitmix(state);
      const bool noise = (r & 1) != 0;
      for (int y = by; y < std::min(by + block, im.height); ++y)
        for (int x = bx; x < std::min(bx + block, im.width); ++x)
          for (int c = 0; c < 3; ++c) {
            float& v = im.data[(static_cast<size_t>(y) * im.width + x) * 3 + c];
            if (noise) v = static_cast<float>((r >> (8 + 8 * c)) & 0xff) / 255.0f;
            else if (invert) v = 1.0f - v;
          }
    }
}

}  // namespace s4d::study
