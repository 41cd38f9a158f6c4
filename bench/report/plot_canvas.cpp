#include "plot_canvas.h"

#include <cmath>
#include <sstream>

namespace s4d::bench {

std::string tick_text(double v, int digits) {
  std::ostringstream s;
  s.precision(std::abs(v) >= 100 ? 0 : digits);
  s << std::fixed << v;
  return s.str();
}

io::ImageF canvas_image(const cv::Mat& rgb) {
  io::ImageF out{rgb.cols, rgb.rows, 3, std::vector<float>(size_t(rgb.cols) * rgb.rows * 3)};
  for (int y = 0; y < rgb.rows; ++y)
    for (int x = 0; x < rgb.cols; ++x)
      for (int c = 0; c < 3; ++c) out.data[(size_t(y) * rgb.cols + x) * 3 + c] = rgb.at<cv::Vec3b>(y, x)[c] / 255.0f;
  return out;
}

}  // namespace s4d::bench
