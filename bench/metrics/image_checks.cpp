#include "s4d/metrics/image_checks.h"

#include <stdexcept>

namespace s4d::metrics {

namespace {
std::string size_of(const io::ImageF& i) {
  return std::to_string(i.width) + "x" + std::to_string(i.height) + "x" + std::to_string(i.channels);
}
}  // namespace

void require_rgb(const io::ImageF& image, const std::string& metric, const std::string& what) {
  if (image.channels != 3 || image.width <= 0 || image.height <= 0 ||
      image.data.size() != size_t(image.width) * size_t(image.height) * 3)
    throw std::invalid_argument(metric + ": " + what + " must be an RGB image with W*H*3 values, got " + size_of(image) +
                                " with " + std::to_string(image.data.size()) + " values");
}

void require_same_rgb(const io::ImageF& a, const io::ImageF& b, const std::string& metric) {
  require_rgb(a, metric, "the first image");
  require_rgb(b, metric, "the second image");
  if (a.width != b.width || a.height != b.height)
    throw std::invalid_argument(metric + ": images differ in size (" + size_of(a) + " vs " + size_of(b) + ")");
}

}  // namespace s4d::metrics
