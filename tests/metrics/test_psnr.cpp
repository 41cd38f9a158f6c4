// PSNR (s4d/io/psnr.h: the trainer's evaluation and Style4D-Bench share it) against values computed
// by hand: a known error gives -10 log10(MSE) exactly, seeded Gaussian noise of sigma s gives about
// -20 log10(s), identical images the documented 100 dB cap, values outside [0, 1] are not clamped.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

#include "metrics_test_util.h"
#include "s4d/io/psnr.h"

using s4d::io::psnr;

TEST_CASE("psnr of identical images is the documented cap") {
  const auto a = s4d::test::lcg_image(16, 12);
  CHECK(psnr(a, a) == doctest::Approx(s4d::io::kPsnrCapDb).epsilon(1e-12));
}

TEST_CASE("psnr of a uniform error d is -20 log10 d") {
  const auto a = s4d::test::constant_image(20, 10, 0.5f, 0.5f, 0.5f);
  auto b = a;
  for (size_t i = 0; i < b.data.size(); ++i) b.data[i] += (i % 2 ? 0.1f : -0.1f);
  // float32 storage of 0.4 / 0.6: relative error of d about 1e-7.
  CHECK(psnr(b, a) == doctest::Approx(20.0).epsilon(1e-6));
}

TEST_CASE("psnr of seeded gaussian noise matches the noise level") {
  const double sigma = 0.05;  // 10 sigma from 0.5 to either end: no clipping
  const auto a = s4d::test::constant_image(64, 64, 0.5f, 0.5f, 0.5f);
  auto b = a;
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, sigma);
  for (float& v : b.data) v = float(v + noise(rng));
  // 12,288 samples: the sample variance has relative spread sqrt(2/N) = 1.3 %, 0.055 dB. Measured
  // 26.0775 against 26.0206 (0.057 dB, one spread) with this seed; 0.2 dB is 3.6 spreads.
  CHECK(psnr(b, a) == doctest::Approx(-20.0 * std::log10(sigma)).epsilon(0.2 / 26.0));
}

TEST_CASE("psnr counts values outside [0, 1] as they are (the evaluator clamps renders before scoring)") {
  const auto target = s4d::test::constant_image(4, 1, 0.5f, 0.5f, 0.5f);
  auto image = s4d::test::constant_image(4, 1, 7.0f, 7.0f, 7.0f);
  CHECK(psnr(image, target) == doctest::Approx(-10 * std::log10(6.5 * 6.5)));  // unclamped: mse 42.25
  for (float& v : image.data) v = std::min(v, 1.0f);                        // what evaluate.cpp scores
  CHECK(psnr(image, target) == doctest::Approx(-10 * std::log10(0.25)));
}

TEST_CASE("psnr refuses images of different sizes") {
  CHECK_THROWS_AS(psnr(s4d::test::lcg_image(8, 8), s4d::test::lcg_image(8, 9)), std::invalid_argument);
}
