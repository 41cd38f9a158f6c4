#include "s4d/metrics/uiqm.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "s4d/metrics/image_checks.h"

namespace s4d::metrics {

UiqmParts uiqm_parts(const io::ImageF& image, UiqmVariant variant) {
  require_rgb(image, "uiqm", "the image");
  if (image.width < 10 || image.height < 10)
    throw std::invalid_argument("uiqm: the image must be at least 10x10, got " + std::to_string(image.width) + "x" +
                                std::to_string(image.height));
  detail::LevelPlanes p{image.width, image.height, {}};
  const size_t n = size_t(image.width) * size_t(image.height);
  for (int c = 0; c < 3; ++c) {
    p.c[c].resize(n);
    for (size_t i = 0; i < n; ++i) p.c[c][i] = std::round(std::clamp(double(image.data[i * 3 + c]), 0.0, 1.0) * 255.0);
  }
  return variant == UiqmVariant::a_funie ? detail::uiqm_funie_gan(p) : detail::uiqm_xueleichen(p);
}

}  // namespace s4d::metrics
