// The weight-free patch stylizer on a frame of the synthetic scene with the built-in style:
// determinism, shapes, the strength knob, and that the result takes the style's colours while
// keeping the content's structure.
#include <doctest/doctest.h>

#include <cmath>

#include "max_abs_diff.h"
#include "s4d/frame_stylizers/builtin_style.h"
#include "s4d/frame_stylizers/patch_stylizer.h"
#include "stylize_fixtures.h"

using namespace s4d;
using test::max_abs_diff;

namespace {

double stats_distance(const std::vector<double>& a, const std::vector<double>& b) {
  double d = 0;
  for (size_t i = 0; i < a.size(); ++i) d += (a[i] - b[i]) * (a[i] - b[i]);
  return std::sqrt(d);
}

const std::vector<io::ImageF>& frame() {
  static const std::vector<io::ImageF> f = test::synth_frames(1);
  return f;
}
const io::ImageF& style() {
  static const io::ImageF s = frame_stylizers::builtin_style(256);
  return s;
}

}  // namespace

TEST_CASE("patch stylizer is deterministic for a seed and keeps the frame size") {
  const frame_stylizers::PatchStylizer stylizer;
  const auto a = stylizer.stylize(frame(), style(), {1.0f, 7});
  const auto b = stylizer.stylize(frame(), style(), {1.0f, 7});
  const auto c = stylizer.stylize(frame(), style(), {1.0f, 8});
  REQUIRE(a.size() == 1);
  CHECK(a[0].width == 160);
  CHECK(a[0].height == 120);
  CHECK(a[0].channels == 3);
  CHECK(a[0].data == b[0].data);
  MESSAGE("seed 7 vs 8 max difference " << max_abs_diff(a[0], c[0]));
  CHECK(max_abs_diff(a[0], c[0]) > 0.1);  // the seed moves the noise and the patch grids; measured 0.76
}

TEST_CASE("strength 0 returns the content and strength blends towards the stylization") {
  const frame_stylizers::PatchStylizer stylizer;
  const auto none = stylizer.stylize(frame(), style(), {0.0f, 0});
  CHECK(max_abs_diff(none[0], frame()[0]) == 0.0);
  const auto full = stylizer.stylize(frame(), style(), {1.0f, 0});
  const auto half = stylizer.stylize(frame(), style(), {0.5f, 0});
  double worst = 0;
  for (size_t i = 0; i < half[0].data.size(); ++i)
    worst = std::max(worst, std::abs(half[0].data[i] - 0.5 * (full[0].data[i] + frame()[0].data[i])));
  CHECK(worst < 1e-5);  // the blend is linear before a clamp that [0, 1] inputs never reach
}

TEST_CASE("the result's colour statistics move to the style's") {
  const auto out = frame_stylizers::PatchStylizer().stylize(frame(), style(), {});
  const auto target = test::colour_stats(style());
  const double before = stats_distance(test::colour_stats(frame()[0]), target);
  const double after = stats_distance(test::colour_stats(out[0]), target);
  MESSAGE("mean/std distance to the style: content " << before << ", result " << after);
  CHECK(after < 0.2 * before);  // measured: content 0.427, result 0.023 (ratio 0.055)
}

TEST_CASE("the result keeps the content's structure") {
  const auto out = frame_stylizers::PatchStylizer().stylize(frame(), style(), {});
  const double r = test::gradient_correlation(frame()[0], out[0]);
  MESSAGE("gradient magnitude correlation with the content " << r);
  CHECK(r > 0.5);  // measured 0.748 (the content against itself: 1)
}

TEST_CASE("patch stylizer refuses bad inputs") {
  const frame_stylizers::PatchStylizer stylizer;
  CHECK_THROWS_AS(stylizer.stylize({}, style(), {}), std::invalid_argument);
  CHECK_THROWS_AS(stylizer.stylize(frame(), style(), {1.5f, 0}), std::invalid_argument);
  std::vector<io::ImageF> mixed = {frame()[0], io::ImageF{8, 8, 3, std::vector<float>(192, 0.5f)}};
  CHECK_THROWS_WITH_AS(stylizer.stylize(mixed, style(), {}), doctest::Contains("frame 1"), std::invalid_argument);
  CHECK_THROWS_AS(stylizer.stylize(frame(), io::ImageF{}, {}), std::invalid_argument);
}
