// SSIM (3DGS convention) against values derived by hand. For constant images a and b with zero
// padding, a pixel whose window covers weight w of the image has mu_a = a w, var_a = a^2 w (1 - w),
// cov = a b w (1 - w), so its SSIM has a closed form; interior pixels (w = 1) give
// (2ab + C1) / (a^2 + b^2 + C1) = 0.98361092 for 100/255 vs 120/255 (METRICS.md 10). No published
// test vector exists for this convention (skimage's and pyiqa's use other windows, borders and data).
#include <doctest/doctest.h>

#include <cmath>
#include <stdexcept>

#include "metrics_test_util.h"
#include "s4d/metrics/ssim.h"

namespace m = s4d::metrics;

TEST_CASE("ssim of identical images is 1") {
  const auto a = s4d::test::lcg_image(23, 17);
  // Each map value is a ratio of equal products; measured |1 - ssim| = 0.
  CHECK(m::ssim(a, a) == doctest::Approx(1.0).epsilon(1e-12));
}

TEST_CASE("ssim of two constant images matches the closed form, borders included") {
  const int w = 30, h = 21;
  const double a = 100.0 / 255, b = 120.0 / 255;
  const auto ia = s4d::test::constant_image(w, h, float(a), float(a), float(a));
  const auto ib = s4d::test::constant_image(w, h, float(b), float(b), float(b));
  const std::vector<double> k = m::ssim_window_1d();
  auto coverage = [&](int p, int n) {
    double s = 0;
    for (int i = -5; i <= 5; ++i)
      if (p + i >= 0 && p + i < n) s += k[size_t(i + 5)];
    return s;
  };
  // a, b as the float32 values the images hold.
  const double fa = double(float(a)), fb = double(float(b));
  double expected = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const double cw = coverage(x, w) * coverage(y, h);
      expected += ((2 * fa * fb * cw * cw + m::kSsimC1) * (2 * fa * fb * cw * (1 - cw) + m::kSsimC2)) /
                  (((fa * fa + fb * fb) * cw * cw + m::kSsimC1) * ((fa * fa + fb * fb) * cw * (1 - cw) + m::kSsimC2));
    }
  expected /= double(w * h);
  const std::vector<double> map = m::ssim_map(ia, ib);
  // Interior: the value METRICS.md gives (8 digits).
  CHECK(map[(size_t(10) * w + 15) * 3] == doctest::Approx(0.98361092).epsilon(1e-8));
  // Both sides in double from the same window; E[x^2] - mu^2 cancels to about 1e-16 absolute.
  CHECK(m::ssim(ia, ib) == doctest::Approx(expected).epsilon(1e-10));
  CHECK(m::ssim(ia, ib) < 0.98361092);  // zero-padded borders lower the mean
}

TEST_CASE("ssim window is the normalised gaussian of sigma 1.5") {
  const std::vector<double> k = m::ssim_window_1d();
  REQUIRE(k.size() == 11);
  double sum = 0;
  for (double v : k) sum += v;
  CHECK(sum == doctest::Approx(1.0).epsilon(1e-15));
  CHECK(k[5] / k[4] == doctest::Approx(std::exp(1.0 / 4.5)).epsilon(1e-14));
  CHECK(k[5] / k[0] == doctest::Approx(std::exp(25.0 / 4.5)).epsilon(1e-14));
}

TEST_CASE("ssim refuses mismatched sizes and non-rgb images") {
  CHECK_THROWS_AS(m::ssim(s4d::test::lcg_image(8, 8), s4d::test::lcg_image(9, 8)), std::invalid_argument);
  s4d::io::ImageF gray{8, 8, 1, std::vector<float>(64, 0.5f)};
  CHECK_THROWS_AS(m::ssim(gray, gray), std::invalid_argument);
}
