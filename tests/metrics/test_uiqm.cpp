// UIQM against independent values: the hand-derived cases of METRICS.md 1 (no published per-image
// values exist), and, for a seeded 37x29 LCG image, uiqm_reference.py: pure-Python line-by-line ports
// of both reference scripts (float64 where the scripts use float32).
#include <doctest/doctest.h>

#include <cmath>
#include <stdexcept>

#include "metrics_test_util.h"
#include "s4d/metrics/uiqm.h"

namespace m = s4d::metrics;
using m::UiqmVariant;

TEST_CASE("uiqm variant A of a constant colour: UICM from the trimmed mean, contrast across channels, no sharpness") {
  const auto im = s4d::test::constant_image(20, 20, 200 / 255.f, 100 / 255.f, 50 / 255.f);
  const m::UiqmParts p = m::uiqm_parts(im);
  CHECK(p.uicm == doctest::Approx(-3.708156).epsilon(1e-6));  // METRICS.md, 7 digits
  CHECK(p.uism == 0.0);   // flat channels: the guarded Sobel gives an all-zero edge map
  // Blocks span the 3 channels: top = 200 - 50, bot = 200 + 50 in each of the 2x2 blocks.
  const double uiconm = -(0.6 * std::log(0.6));
  CHECK(p.uiconm == doctest::Approx(uiconm).epsilon(1e-12));
  CHECK(p.uiqm() == doctest::Approx(0.0282 * -3.708156 + 3.5753 * uiconm).epsilon(1e-6));
  const auto big = s4d::test::constant_image(256, 256, 200 / 255.f, 100 / 255.f, 50 / 255.f);
  CHECK(m::uiqm_parts(big).uicm == doctest::Approx(-3.789592).epsilon(1e-6));
}

TEST_CASE("uiqm variant A contrast of one block with min 50 and max 150 is -(0.5 ln 0.5)") {
  auto im = s4d::test::constant_image(10, 10, 100 / 255.f, 100 / 255.f, 100 / 255.f);
  im.data[0] = 50 / 255.f;
  im.data[157] = 150 / 255.f;
  CHECK(m::uiqm_parts(im).uiconm == doctest::Approx(0.346574).epsilon(1e-6));
}

TEST_CASE("uiqm variant B of a constant colour wraps R + G in uint8 as the script does") {
  const auto im = s4d::test::constant_image(20, 20, 200 / 255.f, 100 / 255.f, 50 / 255.f);
  const m::UiqmParts p = m::uiqm_parts(im, UiqmVariant::b_xueleichen);
  // RG = 100, YB = ((200 + 100) mod 256) / 2 - 50 = -28, no spread.
  CHECK(p.uicm == doctest::Approx(-0.0268 * std::sqrt(100.0 * 100.0 + 28.0 * 28.0)).epsilon(1e-12));
  CHECK(p.uism == 0.0);    // zero edge maps: min and max replaced by 1, ln 1 = 0
  CHECK(p.uiconm == 0.0);  // m = 0 in every block
}

TEST_CASE("uiqm matches the python ports of both reference scripts on a seeded image") {
  const auto im = s4d::test::lcg_image(37, 29);
  // The ports compute in float64 as we do and print 12 significant digits; all 12 agree. 1e-9 allows
  // for summation order.
  const m::UiqmParts a = m::uiqm_parts(im, UiqmVariant::a_funie);
  CHECK(a.uicm == doctest::Approx(21.9095510564).epsilon(1e-9));
  CHECK(a.uism == doctest::Approx(8.06188560364).epsilon(1e-9));
  CHECK(a.uiconm == doctest::Approx(0.000725247216879).epsilon(1e-9));
  CHECK(a.uiqm() == doctest::Approx(3.00111713492).epsilon(1e-9));
  const m::UiqmParts b = m::uiqm_parts(im, UiqmVariant::b_xueleichen);
  CHECK(b.uicm == doctest::Approx(9.51515808509).epsilon(1e-9));
  CHECK(b.uism == doctest::Approx(9.05380614386).epsilon(1e-9));
  CHECK(b.uiconm == doctest::Approx(-0.158988671519).epsilon(1e-9));
  CHECK(b.uiqm() == doctest::Approx(2.373484215).epsilon(1e-9));
}

TEST_CASE("uiqm refuses images smaller than 10x10") {
  CHECK_THROWS_AS(m::uiqm(s4d::test::lcg_image(9, 20)), std::invalid_argument);
}
