// The speed/accuracy trade of a sweep: which settings no other setting beats (cheaper and at least
// as good), and a scatter plot of every setting with that front drawn through it.
#pragma once
#include <string>
#include <vector>

#include "s4d/io/image_io.h"

namespace s4d::bench {

struct TradePoint {
  std::string label;
  double cost = 0;     // lower is better (seconds, MiB)
  double quality = 0;  // higher is better (PSNR, SSIM)
};

// Indices of the points on the Pareto front, by increasing cost: a point is on it when no other
// point has cost <= its cost and quality >= its quality with one of them strict. Of exact
// duplicates, the first stays. Throws std::invalid_argument for a non-finite cost or quality.
std::vector<size_t> pareto_front(const std::vector<TradePoint>& points);

// An RGB scatter plot (900x500): every point labelled, the front's points joined by a line.
// `log_cost` puts cost on a log axis (every cost must then be positive).
io::ImageF pareto_plot(const std::string& title, const std::string& cost_label, const std::string& quality_label,
                       const std::vector<TradePoint>& points, bool log_cost);

}  // namespace s4d::bench
