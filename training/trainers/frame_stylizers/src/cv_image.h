// Views of io::ImageF as OpenCV matrices (no copy) and copies back. OpenCV stays behind the
// library's private headers.
#pragma once
#include <opencv2/core.hpp>

#include "s4d/io/image_io.h"

namespace s4d::frame_stylizers::detail {

// A CV_32FC3 header over an RGB image's data; the image must outlive the view and keep its size.
inline cv::Mat mat_view(io::ImageF& image) { return {image.height, image.width, CV_32FC3, image.data.data()}; }
inline cv::Mat mat_copy(const io::ImageF& image) {
  return cv::Mat(image.height, image.width, CV_32FC3, const_cast<float*>(image.data.data())).clone();
}

// An RGB image from a CV_32FC3 matrix.
io::ImageF image_from(const cv::Mat& rgb);

}  // namespace s4d::frame_stylizers::detail
