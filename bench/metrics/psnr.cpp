#include "s4d/metrics/psnr.h"

#include <algorithm>
#include <cmath>

#include "s4d/metrics/image_checks.h"

namespace s4d::metrics {

double psnr(const io::ImageF& image, const io::ImageF& reference) {
  require_same_rgb(image, reference, "psnr");
  double se = 0;
  for (size_t i = 0; i < image.data.size(); ++i) {
    const double d = double(image.data[i]) - double(reference.data[i]);
    se += d * d;
  }
  const double mse = se / double(image.data.size());
  return -10.0 * std::log10(std::max(mse, kPsnrMinMse));
}

}  // namespace s4d::metrics
