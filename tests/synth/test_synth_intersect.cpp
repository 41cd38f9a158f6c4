// Ray-primitive intersections of the synthetic scene against hits computed by hand.
#include <doctest/doctest.h>

#include <cmath>
#include <numbers>

#include "s4d/synth/intersect.h"
#include "s4d/synth/wave_sheet.h"

using namespace s4d;
using namespace s4d::synth;

namespace {
constexpr double kFar = 1e9;
}

TEST_CASE("sphere: entry point, exit from inside, miss, and s_max cut-off") {
  // Unit sphere at (0, 0, -5) seen from the origin along -z: enters at z = -4, so s = 4.
  const Ray ray{{0, 0, 0}, {0, 0, -1}};
  CHECK(*intersect_sphere(ray, {0, 0, -5}, 1, 0, kFar) == doctest::Approx(4));
  // Off-axis by 0.6: the chord half-length is 0.8, so s = 5 - 0.8.
  CHECK(*intersect_sphere({{0.6, 0, 0}, {0, 0, -1}}, {0, 0, -5}, 1, 0, kFar) == doctest::Approx(4.2));
  // From the centre the only forward hit is the exit at s = radius.
  CHECK(*intersect_sphere({{0, 0, -5}, {0, 0, -1}}, {0, 0, -5}, 1, 0, kFar) == doctest::Approx(1));
  CHECK_FALSE(intersect_sphere({{1.01, 0, 0}, {0, 0, -1}}, {0, 0, -5}, 1, 0, kFar));
  CHECK_FALSE(intersect_sphere(ray, {0, 0, -5}, 1, 0, 3.9));
  CHECK_FALSE(intersect_sphere(ray, {0, 0, 5}, 1, 0, kFar));  // behind the origin
}

TEST_CASE("plane: hit distance along a slanted ray, parallel rays miss") {
  // Floor y = -1 from (0, 1, 0) along (0, -1, 1)/sqrt 2: 2 down means 2 sqrt 2 along the ray.
  const Ray ray{{0, 1, 0}, normalize(Vec3{0, -1, 1})};
  CHECK(*intersect_plane(ray, {0, -1, 0}, {0, 1, 0}, 0, kFar) == doctest::Approx(2 * std::sqrt(2.0)));
  CHECK_FALSE(intersect_plane({{0, 1, 0}, {1, 0, 0}}, {0, -1, 0}, {0, 1, 0}, 0, kFar));
  CHECK_FALSE(intersect_plane({{0, 1, 0}, {0, 1, 0}}, {0, -1, 0}, {0, 1, 0}, 0, kFar));  // pointing away
}

TEST_CASE("box: the face entered, the exit from inside, misses") {
  const Vec3 half{1, 0.5, 2};
  auto front = intersect_box({{0, 0, 5}, {0, 0, -1}}, half, 0, kFar);
  REQUIRE(front);
  CHECK(front->s == doctest::Approx(3));
  CHECK(front->axis == 2);
  CHECK(front->sign == 1);
  auto side = intersect_box({{-4, 0.2, 0.3}, {1, 0, 0}}, half, 0, kFar);
  REQUIRE(side);
  CHECK(side->s == doctest::Approx(3));
  CHECK(side->axis == 0);
  CHECK(side->sign == -1);
  // Diagonal in the x-y plane from (-2, -2, 0): the y slab (|y| <= 0.5) is entered last at y = -0.5.
  auto diag = intersect_box({{-2, -2, 0}, normalize(Vec3{1, 1, 0})}, half, 0, kFar);
  REQUIRE(diag);
  CHECK(diag->s == doctest::Approx(1.5 * std::sqrt(2.0)));
  CHECK(diag->axis == 1);
  CHECK(diag->sign == -1);
  auto inside = intersect_box({{0, 0, 0}, {0, 1, 0}}, half, 0, kFar);
  REQUIRE(inside);
  CHECK(inside->s == doctest::Approx(0.5));
  CHECK(inside->sign == 1);
  CHECK_FALSE(intersect_box({{0, 0.6, 5}, {0, 0, -1}}, half, 0, kFar));
  CHECK_FALSE(intersect_box({{0, 0, 5}, {0, 0, 1}}, half, 0, kFar));
}

TEST_CASE("wave sheet: hits z(x, t) at known times, pinned edge, outside the rectangle misses") {
  const WaveSheet w;  // x in [-0.5, 1.5], y in [0.2, 1.2], z0 = -1.2, amplitude 0.2, wavelength 1
  // At x = 1.25: (x - x0) = 1.75 wavelengths, amplitude factor 0.2 * 1.75 / 2 = 0.175.
  // t = 0: sin(3.5 pi) = -1, so z = -1.375; t = 0.5: sin(2.5 pi) = +1, so z = -1.025.
  CHECK(w.depth(1.25, 0.0) == doctest::Approx(-1.375));
  CHECK(w.depth(1.25, 0.5) == doctest::Approx(-1.025));
  const Ray down{{1.25, 0.7, 5}, {0, 0, -1}};
  CHECK(*intersect_wave_sheet(down, w, 0.0, 0, kFar) == doctest::Approx(6.375).epsilon(1e-9));
  CHECK(*intersect_wave_sheet(down, w, 0.5, 0, kFar) == doctest::Approx(6.025).epsilon(1e-9));
  // t = 0.25 at x = 1.25: sin(3 pi) = 0, so the sheet is at z0 and the normal has slope
  // 0.175 * 2 pi * cos(3 pi) = -0.35 pi, i.e. normal ~ (0.35 pi, 0, 1).
  CHECK(*intersect_wave_sheet(down, w, 0.25, 0, kFar) == doctest::Approx(6.2).epsilon(1e-9));
  const Vec3 n = w.normal(1.25, 0.25);
  CHECK(n[0] / n[2] == doctest::Approx(0.35 * std::numbers::pi));
  // The pole edge x = x0 never moves.
  CHECK(w.depth(-0.5, 0.3) == doctest::Approx(-1.2));
  // A slanted ray still lands on the surface.
  const Ray slant{{0, 0.6, 3}, normalize(Vec3{0.3, 0.05, -1})};
  const auto s = intersect_wave_sheet(slant, w, 0.7, 0, kFar);
  REQUIRE(s);
  const Vec3 p = slant.at(*s);
  CHECK(p[2] == doctest::Approx(w.depth(p[0], 0.7)).epsilon(1e-9));
  CHECK_FALSE(intersect_wave_sheet({{1.25, 1.3, 5}, {0, 0, -1}}, w, 0.0, 0, kFar));  // above y1
  CHECK_FALSE(intersect_wave_sheet({{1.6, 0.7, 5}, {0, 0, -1}}, w, 0.0, 0, kFar));   // right of x1
  CHECK_FALSE(intersect_wave_sheet(down, w, 0.0, 0, 6.0));                           // s_max before it
}
