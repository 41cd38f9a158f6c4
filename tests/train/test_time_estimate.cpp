// time_estimate.h: the run's length from its measured first steps.
#include <doctest/doctest.h>

#include <cmath>

#include "s4d/train/time_estimate.h"

using namespace s4d;

TEST_CASE("time estimate: a cloud already at its budget costs the measured step throughout") {
  run::TrainConfig c = run::preset_config("fast");
  c.budget = 5000;
  c.fine_batch = 2;
  const train::TimeEstimate e = train::estimate_time(c, 0.2, 5000);
  CHECK(e.static_seconds == doctest::Approx(0.2 * c.iterations));
  CHECK(e.fine_seconds == doctest::Approx(0.2 * 2.5 * 2 * c.fine_iterations));  // 2.5 static steps per 4DGS view
  CHECK(e.static_seconds_low == doctest::Approx(e.static_seconds));
  CHECK(e.fine_seconds_low == doctest::Approx(0.2 * 2 * c.fine_iterations));
}

TEST_CASE("time estimate: growth to the budget over the densification window, Gaussians^0.5 and ^0.65") {
  run::TrainConfig c = run::preset_config("fast");  // 900 static: densify 300..700; budget 15000
  const double s = 0.1, n0 = 3750;                       // budget / 4
  const train::TimeEstimate e = train::estimate_time(c, s, static_cast<uint32_t>(n0));
  // Before the window at 1x, after it at 4^0.5 = 2x, during it the mean of sqrt over a linear ramp
  // from 1 to 4: (2/3)(4^1.5 - 1) / 3 = 14/9 (the 64-point midpoint rule is within 1e-4 of it).
  const double expected = s * (300 + 400 * 14.0 / 9.0 + 200 * 2.0);
  CHECK(e.static_seconds == doctest::Approx(expected).epsilon(1e-4));
  CHECK(e.fine_seconds == doctest::Approx(s * 2.5 * 1 * c.fine_iterations * std::pow(4.0, 0.65)));
  CHECK(e.static_seconds_low == doctest::Approx(s * 900));
  // 90 s to 132 s, and 150 s to 923 s, in whole minutes.
  CHECK(train::describe(e, 30).starts_with("estimate: static stage 2 min to 2 min, 4DGS stage 2 min to 15 min ("));
  run::TrainConfig static_only = c;
  static_only.fine_iterations = 0;
  CHECK(train::describe(train::estimate_time(static_only, s, 3750), 30).find("4DGS") == std::string::npos);
}
