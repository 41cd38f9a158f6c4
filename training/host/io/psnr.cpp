#include "s4d/io/psnr.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace s4d::io {

namespace {
std::string shape_of(const ImageF& i) {
  return std::to_string(i.width) + "x" + std::to_string(i.height) + "x" + std::to_string(i.channels) + " with " +
         std::to_string(i.data.size()) + " values";
}
}  // namespace

double psnr(const ImageF& image, const ImageF& reference) {
  const bool whole = image.width > 0 && image.height > 0 && image.channels > 0 &&
                     image.data.size() == size_t(image.width) * size_t(image.height) * size_t(image.channels);
  if (!whole || image.width != reference.width || image.height != reference.height ||
      image.channels != reference.channels || image.data.size() != reference.data.size())
    throw std::invalid_argument("psnr: needs two non-empty images of the same shape, got " + shape_of(image) + " and " +
                                shape_of(reference));
  double se = 0;
  for (size_t i = 0; i < image.data.size(); ++i) {
    const double d = double(image.data[i]) - double(reference.data[i]);
    se += d * d;
  }
  const double mse = se / double(image.data.size());
  return -10.0 * std::log10(std::max(mse, kPsnrMinMse));
}

}  // namespace s4d::io
