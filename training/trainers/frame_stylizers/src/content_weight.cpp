#include "content_weight.h"

#include <algorithm>
#include <vector>

#include <opencv2/imgproc.hpp>

namespace s4d::frame_stylizers::detail {

cv::Mat content_weight(const cv::Mat& content, float floor, float peak) {
  cv::Mat gray, gx, gy, magnitude;
  cv::cvtColor(content, gray, cv::COLOR_RGB2GRAY);
  cv::GaussianBlur(gray, gray, cv::Size(0, 0), 1.0);
  cv::Sobel(gray, gx, CV_32F, 1, 0);
  cv::Sobel(gray, gy, CV_32F, 0, 1);
  cv::magnitude(gx, gy, magnitude);

  std::vector<float> values(magnitude.begin<float>(), magnitude.end<float>());
  auto p90 = values.begin() + static_cast<std::ptrdiff_t>(values.size() * 9 / 10);
  std::nth_element(values.begin(), p90, values.end());
  // A flat image has no edges: every pixel gets the floor (1e-6 keeps the division finite).
  const float scale = *p90 > 1e-6f ? *p90 : 1.0f;
  cv::Mat edges = cv::min(magnitude / scale, 1.0);
  cv::dilate(edges, edges, cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(3, 3)));
  cv::GaussianBlur(edges, edges, cv::Size(0, 0), 1.5);
  return floor + (peak - floor) * edges;
}

}  // namespace s4d::frame_stylizers::detail
