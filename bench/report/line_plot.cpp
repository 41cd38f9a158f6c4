#include "s4d/bench/line_plot.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "plot_canvas.h"

namespace s4d::bench {

namespace {

constexpr int kW = 800, kH = 450, kLeft = 90, kRight = 170, kTop = 55, kBottom = 60;

// Colours (RGB) that stay apart for a handful of methods.
const cv::Scalar kColours[] = {{31, 119, 180}, {214, 39, 40}, {44, 160, 44}, {255, 127, 14}, {148, 103, 189}, {140, 86, 75}};

}  // namespace

io::ImageF line_plot(const std::string& title, const std::string& x_label, const std::string& y_label,
                     const std::vector<Series>& series) {
  if (series.empty()) throw std::invalid_argument("line_plot '" + title + "': no series");
  double lo = INFINITY, hi = -INFINITY;
  size_t n = 0;
  for (const auto& s : series) {
    if (s.values.empty()) throw std::invalid_argument("line_plot '" + title + "': series '" + s.name + "' is empty");
    for (double v : s.values) lo = std::min(lo, v), hi = std::max(hi, v);
    n = std::max(n, s.values.size());
  }
  if (hi - lo < 1e-12) lo -= 0.5, hi += 0.5;  // a flat curve still gets a y range
  const double pad = 0.05 * (hi - lo);
  lo -= pad, hi += pad;
  cv::Mat img(kH, kW, CV_8UC3, cv::Scalar(255, 255, 255));
  const int x0 = kLeft, x1 = kW - kRight, y0 = kH - kBottom, y1 = kTop;
  auto px = [&](double i) { return x0 + int(std::lround((n > 1 ? i / double(n - 1) : 0.5) * (x1 - x0))); };
  auto py = [&](double v) { return y0 - int(std::lround((v - lo) / (hi - lo) * (y0 - y1))); };
  const cv::Scalar black(0, 0, 0), grid(225, 225, 225);
  const int font = cv::FONT_HERSHEY_SIMPLEX;
  for (int t = 0; t <= 5; ++t) {  // y ticks
    const double v = lo + (hi - lo) * t / 5;
    cv::line(img, {x0, py(v)}, {x1, py(v)}, grid, 1);
    cv::line(img, {x0 - 5, py(v)}, {x0, py(v)}, black, 1);
    cv::putText(img, tick_text(v, 3), {8, py(v) + 4}, font, 0.4, black, 1, cv::LINE_AA);
  }
  const int xticks = int(std::min<size_t>(n, 6));
  for (int t = 0; t < xticks; ++t) {  // x ticks at whole indices
    const double i = xticks > 1 ? std::round(double(n - 1) * t / (xticks - 1)) : 0;
    cv::line(img, {px(i), y0}, {px(i), y0 + 5}, black, 1);
    cv::putText(img, std::to_string(int(i)), {px(i) - 6, y0 + 20}, font, 0.4, black, 1, cv::LINE_AA);
  }
  cv::line(img, {x0, y0}, {x1, y0}, black, 1);
  cv::line(img, {x0, y0}, {x0, y1}, black, 1);
  cv::putText(img, title, {x0, 22}, font, 0.6, black, 1, cv::LINE_AA);
  cv::putText(img, x_label, {(x0 + x1) / 2 - 40, kH - 15}, font, 0.5, black, 1, cv::LINE_AA);
  cv::putText(img, y_label, {8, y1 - 14}, font, 0.45, black, 1, cv::LINE_AA);
  for (size_t k = 0; k < series.size(); ++k) {
    const cv::Scalar colour = kColours[k % std::size(kColours)];
    const auto& v = series[k].values;
    for (size_t i = 1; i < v.size(); ++i) cv::line(img, {px(double(i - 1)), py(v[i - 1])}, {px(double(i)), py(v[i])}, colour, 2, cv::LINE_AA);
    if (v.size() == 1) cv::circle(img, {px(0), py(v[0])}, 3, colour, -1);
    const int ly = y1 + 20 * int(k) + 10;
    cv::line(img, {x1 + 15, ly}, {x1 + 40, ly}, colour, 2);
    cv::putText(img, series[k].name, {x1 + 45, ly + 4}, font, 0.45, black, 1, cv::LINE_AA);
  }
  return canvas_image(img);
}

}  // namespace s4d::bench
