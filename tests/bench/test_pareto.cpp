// The Pareto front of a sweep against fronts worked out by hand, and its plot.
#include <doctest/doctest.h>

#include <cmath>
#include <stdexcept>

#include "s4d/bench/pareto.h"

using s4d::bench::pareto_front;
using s4d::bench::TradePoint;

TEST_CASE("the Pareto front keeps exactly the settings nothing cheaper beats") {
  // b is beaten by a (cheaper, better); d by c (same cost, worse); e is the most expensive but best.
  const std::vector<TradePoint> p = {{"a", 10, 25}, {"b", 12, 24}, {"c", 20, 27}, {"d", 20, 26}, {"e", 40, 28}, {"f", 5, 20}};
  CHECK(pareto_front(p) == std::vector<size_t>{5, 0, 2, 4});
  // Equal quality at a higher cost is beaten; of exact duplicates the first stays.
  CHECK(pareto_front({{"x", 1, 5}, {"y", 2, 5}}) == std::vector<size_t>{0});
  CHECK(pareto_front({{"x", 1, 5}, {"y", 1, 5}}) == std::vector<size_t>{0});
  CHECK(pareto_front({{"only", 3, 1}}) == std::vector<size_t>{0});
  CHECK(pareto_front({}).empty());
  CHECK_THROWS_AS(pareto_front({{"nan", NAN, 1}}), std::invalid_argument);
}

TEST_CASE("the Pareto plot draws the front's points in its colour and refuses a log axis at zero cost") {
  const std::vector<TradePoint> p = {{"a", 10, 25}, {"b", 12, 24}, {"c", 20, 27}};
  const s4d::io::ImageF img = s4d::bench::pareto_plot("t", "seconds", "psnr", p, true);
  CHECK(img.width == 900);
  CHECK(img.height == 500);
  size_t red = 0, grey = 0;  // front points are red (214, 39, 40), the beaten one grey (120, 120, 120)
  for (size_t i = 0; i < img.data.size(); i += 3) {
    const float r = img.data[i] * 255, g = img.data[i + 1] * 255, b = img.data[i + 2] * 255;
    red += std::abs(r - 214) < 1 && std::abs(g - 39) < 1 && std::abs(b - 40) < 1;
    grey += std::abs(r - 120) < 1 && std::abs(g - 120) < 1 && std::abs(b - 120) < 1;
  }
  CHECK(red > 100);  // two filled discs and the line between them
  CHECK(grey > 20);  // one filled disc
  CHECK_THROWS_AS(s4d::bench::pareto_plot("t", "s", "q", {{"z", 0, 1}}, true), std::invalid_argument);
}
