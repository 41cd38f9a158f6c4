// The largest |a[i] - b[i]| over two arrays or images of one size: one number that bounds a whole
// result, for tests whose tolerance is a single bound (element-wise ones use expect_allclose.h).
// A NaN on either side gives +infinity, so that "<= tol" fails where std::max would drop the NaN.
#pragma once
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

namespace s4d::test {

template <class A, class B>
double max_abs_diff(const A& a, const B& b) {
  REQUIRE(a.size() == b.size());
  double worst = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    const double d = std::abs(static_cast<double>(a[i]) - static_cast<double>(b[i]));
    if (std::isnan(d)) return std::numeric_limits<double>::infinity();
    worst = std::max(worst, d);
  }
  return worst;
}

// Images (io::ImageF or anything with width, height, channels and data) of one shape.
template <class Image>
  requires requires(const Image& i) { i.width, i.height, i.channels, i.data; }
double max_abs_diff(const Image& a, const Image& b) {
  REQUIRE(a.width == b.width);
  REQUIRE(a.height == b.height);
  REQUIRE(a.channels == b.channels);
  return max_abs_diff(a.data, b.data);
}

}  // namespace s4d::test
