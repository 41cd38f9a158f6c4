// The time budget's planning (time_budget.h): the stages' split from the estimate, a stage's length
// from a deadline and a measured step time, schedules scaled from the run's starting settings, and
// the state a checkpoint keeps.
#include <doctest/doctest.h>

#include "s4d/run/train_config.h"
#include "s4d/train/time_budget.h"

using namespace s4d;

TEST_CASE("time budget: the static share is the estimate's split at the middle of each stage's range") {
  train::TimeEstimate e;
  e.static_seconds_low = 10, e.static_seconds = 40;  // middle 20
  e.fine_seconds_low = 20, e.fine_seconds = 180;     // middle 60
  CHECK(train::static_share(e) == doctest::Approx(0.25));
  e.fine_seconds_low = e.fine_seconds = 0;  // no fine stage
  CHECK(train::static_share(e) == 1.0);
}

TEST_CASE("time budget: a stage's length fits its deadline, never below the steps done nor above the stretch cap") {
  // 30 s left at 0.5 s per step: 60 more after the 100 done.
  CHECK(train::fitted_length(130, 100, 100, 0.5, 1000) == 160);
  CHECK(train::fitted_length(130, 100, 100, 0.7, 1000) == 142);  // floor(42.9)
  CHECK(train::fitted_length(90, 100, 100, 0.5, 1000) == 100);   // past the deadline: ends now
  CHECK(train::fitted_length(1e6, 0, 10, 0.5, 300) == 1200);     // at most kMaxStretch x the starting length
  CHECK(train::fitted_length(1e6, 0, 5000, 0.5, 300) == 5000);   // never below the steps done
  CHECK(train::fitted_length(100, 0, 10, 0.0, 300) == 1200);     // no step time measured: the cap
}

TEST_CASE("time budget: schedules scale from the starting settings, whatever earlier plans did") {
  run::TrainConfig start = run::preset_config("fast");
  run::TrainConfig c = start;
  c.lr_scale = 0.25;  // halved twice by rollbacks: kept
  train::fit_schedules(c, start, 450, 3000);
  CHECK(c.iterations == 450);
  CHECK(c.densify_from == start.densify_from / 2);
  CHECK(c.densify_until == start.densify_until / 2);
  CHECK(c.fine_iterations == 3000);
  CHECK(c.fine_densify_until == start.fine_densify_until * 2);
  CHECK(c.lr_scale == 0.25);
  train::fit_schedules(c, start, 900, 1500);  // back to the start: exactly its schedules
  CHECK(run::to_json(c) == [&] {
    run::TrainConfig s = start;
    s.lr_scale = 0.25;
    return run::to_json(s);
  }());
  run::TrainConfig static_only = start;
  static_only.fine_iterations = 0;
  train::fit_schedules(static_only, static_only, 100, 50);
  CHECK(static_only.fine_iterations == 0);  // no fine stage appears
}

TEST_CASE("time budget: the state round-trips through a checkpoint's JSON and refuses a broken one") {
  train::BudgetState s;
  s.static_share = 0.3;
  s.start = run::preset_config("fast");
  s.start.time_budget = 600;
  s.from_iteration = 40, s.from_seconds = 12.5;
  s.plans.push_back({{"stage", "static"}, {"iteration", 50}});
  const train::BudgetState back = train::BudgetState::from_json(s.to_json());
  CHECK(back.to_json() == s.to_json());
  nlohmann::json broken = s.to_json();
  broken.erase("from_seconds");
  CHECK_THROWS_WITH_AS(train::BudgetState::from_json(broken), doctest::Contains("time_budget"), std::runtime_error);
}
