#include "cv_image.h"

#include <stdexcept>

namespace s4d::frame_stylizers::detail {

io::ImageF image_from(const cv::Mat& rgb) {
  if (rgb.type() != CV_32FC3) throw std::invalid_argument("image_from: expected a CV_32FC3 matrix");
  io::ImageF image{rgb.cols, rgb.rows, 3, {}};
  image.data.resize(static_cast<size_t>(rgb.rows) * static_cast<size_t>(rgb.cols) * 3);
  cv::Mat view = mat_view(image);
  rgb.copyTo(view);
  return image;
}

}  // namespace s4d::frame_stylizers::detail
