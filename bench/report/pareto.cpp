#include "s4d/bench/pareto.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "plot_canvas.h"

namespace s4d::bench {

namespace {

constexpr int kW = 900, kH = 500, kLeft = 70, kRight = 100, kTop = 50, kBottom = 60;

// [lo, hi] padded by 5%, or a unit range around a single value.
std::pair<double, double> padded(double lo, double hi) {
  if (hi - lo < 1e-12) return {lo - 0.5, hi + 0.5};
  const double pad = 0.05 * (hi - lo);
  return {lo - pad, hi + pad};
}

}  // namespace

std::vector<size_t> pareto_front(const std::vector<TradePoint>& points) {
  for (const TradePoint& p : points)
    if (!std::isfinite(p.cost) || !std::isfinite(p.quality))
      throw std::invalid_argument("pareto_front: point '" + p.label + "' has a non-finite cost or quality");
  std::vector<size_t> order(points.size());
  std::iota(order.begin(), order.end(), size_t{0});
  // By cost, then best quality first, then input order: a point is on the front when its quality
  // beats every cheaper-or-equal point's before it.
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    if (points[a].cost != points[b].cost) return points[a].cost < points[b].cost;
    return points[a].quality > points[b].quality;
  });
  std::vector<size_t> front;
  double best = -INFINITY;
  for (size_t i : order)
    if (points[i].quality > best) {
      front.push_back(i);
      best = points[i].quality;
    }
  return front;
}

io::ImageF pareto_plot(const std::string& title, const std::string& cost_label, const std::string& quality_label,
                       const std::vector<TradePoint>& points, bool log_cost) {
  if (points.empty()) throw std::invalid_argument("pareto_plot '" + title + "': no points");
  const std::vector<size_t> front = pareto_front(points);
  auto cx = [&](double c) {
    if (log_cost && !(c > 0)) throw std::invalid_argument("pareto_plot '" + title + "': a log cost axis needs positive costs");
    return log_cost ? std::log10(c) : c;
  };
  double clo = INFINITY, chi = -INFINITY, qlo = INFINITY, qhi = -INFINITY;
  for (const TradePoint& p : points) {
    clo = std::min(clo, cx(p.cost)), chi = std::max(chi, cx(p.cost));
    qlo = std::min(qlo, p.quality), qhi = std::max(qhi, p.quality);
  }
  std::tie(clo, chi) = padded(clo, chi);
  std::tie(qlo, qhi) = padded(qlo, qhi);
  cv::Mat img(kH, kW, CV_8UC3, cv::Scalar(255, 255, 255));
  const int x0 = kLeft, x1 = kW - kRight, y0 = kH - kBottom, y1 = kTop;
  auto px = [&](double c) { return x0 + int(std::lround((cx(c) - clo) / (chi - clo) * (x1 - x0))); };
  auto py = [&](double q) { return y0 - int(std::lround((q - qlo) / (qhi - qlo) * (y0 - y1))); };
  const cv::Scalar black(0, 0, 0), grid(225, 225, 225), other(120, 120, 120), on_front(214, 39, 40);
  const int font = cv::FONT_HERSHEY_SIMPLEX;
  for (int t = 0; t <= 5; ++t) {
    const double q = qlo + (qhi - qlo) * t / 5, c = clo + (chi - clo) * t / 5;
    const int y = y0 - (y0 - y1) * t / 5, x = x0 + (x1 - x0) * t / 5;
    cv::line(img, {x0, y}, {x1, y}, grid, 1);
    cv::putText(img, tick_text(q, 2), {8, y + 4}, font, 0.4, black, 1, cv::LINE_AA);
    cv::line(img, {x, y0}, {x, y0 + 5}, black, 1);
    cv::putText(img, tick_text(log_cost ? std::pow(10.0, c) : c, 2), {x - 14, y0 + 20}, font, 0.4, black, 1, cv::LINE_AA);
  }
  cv::line(img, {x0, y0}, {x1, y0}, black, 1);
  cv::line(img, {x0, y0}, {x0, y1}, black, 1);
  cv::putText(img, title, {x0, 22}, font, 0.6, black, 1, cv::LINE_AA);
  cv::putText(img, cost_label + (log_cost ? " (log scale)" : ""), {(x0 + x1) / 2 - 60, kH - 15}, font, 0.5, black, 1, cv::LINE_AA);
  cv::putText(img, quality_label, {8, y1 - 14}, font, 0.45, black, 1, cv::LINE_AA);
  for (size_t k = 1; k < front.size(); ++k)
    cv::line(img, {px(points[front[k - 1]].cost), py(points[front[k - 1]].quality)},
             {px(points[front[k]].cost), py(points[front[k]].quality)}, on_front, 2, cv::LINE_AA);
  for (size_t i = 0; i < points.size(); ++i) {
    const bool best = std::find(front.begin(), front.end(), i) != front.end();
    const cv::Point at{px(points[i].cost), py(points[i].quality)};
    cv::circle(img, at, best ? 5 : 4, best ? on_front : other, -1, cv::LINE_AA);
    cv::putText(img, points[i].label, {at.x + 7, at.y - 6}, font, 0.35, best ? on_front : other, 1, cv::LINE_AA);
  }
  return canvas_image(img);
}

}  // namespace s4d::bench
