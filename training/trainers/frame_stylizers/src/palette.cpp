#include "palette.h"

#include <algorithm>
#include <numeric>
#include <stdexcept>

namespace s4d::frame_stylizers::detail {

Palette::Palette(const cv::Mat& style) {
  if (style.type() != CV_32FC3 || style.empty()) throw std::invalid_argument("Palette: expected a CV_32FC3 style");
  const cv::Mat s = style.isContinuous() ? style : style.clone();
  const size_t n = s.total();
  const float* p = s.ptr<float>();
  for (int c = 0; c < 3; ++c) {
    sorted_[c].resize(n);
    for (size_t i = 0; i < n; ++i) sorted_[c][i] = p[3 * i + c];
    std::sort(sorted_[c].begin(), sorted_[c].end());
  }
}

cv::Mat Palette::apply(const cv::Mat& image) const {
  const cv::Mat in = image.isContinuous() ? image : image.clone();
  cv::Mat out(in.size(), CV_32FC3);
  const size_t n = in.total();
  const float* src = in.ptr<float>();
  float* dst = out.ptr<float>();
  std::vector<size_t> order(n);
  for (int c = 0; c < 3; ++c) {
    std::iota(order.begin(), order.end(), size_t{0});
    std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return src[3 * a + c] < src[3 * b + c]; });
    const std::vector<float>& target = sorted_[c];
    // Equal values form one run and all take the style value at the run's middle quantile, so a
    // flat region stays flat instead of becoming a ramp in scan order.
    for (size_t begin = 0; begin < n;) {
      size_t end = begin + 1;
      while (end < n && src[3 * order[end] + c] == src[3 * order[begin] + c]) ++end;
      const size_t j = std::min(target.size() - 1, (begin + end) * target.size() / (2 * n));
      for (size_t rank = begin; rank < end; ++rank) dst[3 * order[rank] + c] = target[j];
      begin = end;
    }
  }
  return out;
}

}  // namespace s4d::frame_stylizers::detail
