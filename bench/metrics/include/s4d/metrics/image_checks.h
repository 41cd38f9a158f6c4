// Shape checks shared by the metrics: every metric takes RGB frames (io::ImageF, [H, W, 3], values in
// [0, 1]) and names the metric and the offending image in its errors.
#pragma once
#include <string>

#include "s4d/io/image_io.h"

namespace s4d::metrics {

// Throws std::invalid_argument("<metric>: <what> must be an RGB image ...") unless `image` has 3
// channels, a positive size and width * height * 3 values.
void require_rgb(const io::ImageF& image, const std::string& metric, const std::string& what);

// require_rgb on both, then the same width and height; the error names both sizes.
void require_same_rgb(const io::ImageF& a, const io::ImageF& b, const std::string& metric);

}  // namespace s4d::metrics
