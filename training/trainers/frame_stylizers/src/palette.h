// Colour transfer to the style's palette by per-channel histogram matching: each value becomes the
// style's value at the same quantile of its channel (Elad & Milanfar's colour transfer, steps 0
// and (d)).
#pragma once
#include <array>
#include <vector>

#include <opencv2/core.hpp>

namespace s4d::frame_stylizers::detail {

class Palette {
 public:
  explicit Palette(const cv::Mat& style);  // CV_32FC3
  // CV_32FC3 of the same size; equal values map to one value, so the result is deterministic.
  cv::Mat apply(const cv::Mat& image) const;

 private:
  std::array<std::vector<float>, 3> sorted_;  // the style's values per channel, ascending
};

}  // namespace s4d::frame_stylizers::detail
