// The time budget's planning (time_budget.h): the stages' split from the estimate, a stage's length
// from a deadline and a measured step time, schedules scaled from the run's starting settings, and
// the state a checkpoint keeps.
#include <tuple>

#include <doctest/doctest.h>

#include "s4d/run/train_config.h"
#include "s4d/train/time_budget.h"

using namespace s4d;

TEST_CASE("time budget: a fine step's cost in static steps is the estimate's, at the middle of each stage's range") {
  train::TimeEstimate e;
  e.static_seconds_low = 10, e.static_seconds = 40;  // middle 20 over 900 steps
  e.fine_seconds_low = 20, e.fine_seconds = 180;     // middle 60 over 1500 steps
  run::TrainConfig c = run::preset_config("fast");
  CHECK(train::fine_step_ratio(e, c) == doctest::Approx((60.0 / 1500) / (20.0 / 900)));
  c.fine_iterations = 0;
  CHECK(train::fine_step_ratio(e, c) == 0);
}

TEST_CASE("time budget: one factor on both stages makes the steps left end at the deadline") {
  // 100 of 900 static steps done at 10 s; 0.1 s a static step, 0.3 s a fine one: scale f costs
  // (900 f - 100) 0.1 + 1500 f 0.3 = 540 f - 10, so 260 s left (a deadline at 270 s) gives f = 0.5.
  CHECK(train::fitted_scale(270, 10, 100, 0.1, 3.0, 900, 1500) == doctest::Approx(0.5));
  // Past the deadline: fewer static steps than done (the stage ends now), next to no fine ones.
  CHECK(train::fitted_scale(5, 10, 100, 0.1, 3.0, 900, 1500) * 900 < 100);
  CHECK(train::fitted_scale(-1e3, 10, 100, 0.1, 3.0, 900, 1500) == 0);
  CHECK(train::fitted_scale(1e9, 10, 100, 0.1, 3.0, 900, 1500) == train::kMaxStretch);
  CHECK(train::fitted_scale(100, 0, 0, 0.0, 3.0, 900, 1500) == train::kMaxStretch);  // no step time measured
}

namespace {

// fast's 900 + 1,500 steps, 100 static steps done at 10 s, 0.1 s a static step and 0.3 s a fine
// one, for a deadline at `deadline` s: the lengths and which floors held.
std::tuple<uint32_t, uint32_t, bool, bool> fast_lengths(double deadline) {
  const train::StageLengths l = train::fitted_lengths(deadline, 10, 100, 0.1, 3.0, 900, 1500);
  return {l.static_steps, l.fine_steps, l.static_floor, l.fine_floor};
}

}  // namespace

TEST_CASE("time budget: each stage keeps a quarter of its length, the static stage at most its own; the fine stage gets the time the static stage leaves") {
  // Room for scale 0.5 (the case above): both stages scaled, no floor.
  CHECK(fast_lengths(270) == std::tuple{450u, 750u, false, false});
  // 150 s left: scale (150 + 10) / 540 = 0.296 gives 267 static steps, 444 fine; no floor.
  CHECK(fast_lengths(160) == std::tuple{267u, 444u, false, false});
  // 120 s left: scale 130 / 540 = 0.241 would give 217 static steps, under the floor of 225. The
  // static stage takes 225 (125 more, 12.5 s), and the 107.5 s left would give the fine stage 358
  // steps at 0.3 s, under its floor of 375: it takes 375. One scale for both stages puts either
  // under its floor only with the other.
  CHECK(fast_lengths(130) == std::tuple{225u, 375u, true, true});
  // Twice the time the recipe takes: the static stage stays at its 900 (80 s), and the fine stage
  // gets the 1,000 s left at 0.3 s, 3,333 steps (at most 4 x 1,500).
  CHECK(fast_lengths(1090) == std::tuple{900u, 3333u, false, false});
  CHECK(train::fitted_lengths(1e6, 10, 100, 0.1, 3.0, 900, 1500).fine_steps == 6000);
  CHECK(train::fitted_lengths(1e6, 10, 1000, 0.1, 3.0, 900, 1500).static_steps == 1000);  // past the recipe: ends now
  // The time gone: the floors would cost more than 1.5 x the time left, so the static stage ends
  // now and the fine stage gets one step.
  CHECK(fast_lengths(5) == std::tuple{100u, 1u, false, false});
  CHECK(train::fitted_lengths(5, 10, 300, 0.1, 3.0, 900, 1500).fine_steps == 1);
  // 80 s left: the floors cost 125 s, over 1.5 x 80, so the scaled lengths stand (0.167 x).
  CHECK(fast_lengths(90) == std::tuple{150u, 250u, false, false});
  // 600 static steps done at 10 s, 0.125 s a static step and 0.25 s a fine one, 156 s left: scale
  // (156 + 75) / 487.5 = 0.474 would give 426 static steps, fewer than done. The stage ends at 600
  // and the fine stage gets the 156 s: 624 steps.
  const train::StageLengths done = train::fitted_lengths(166, 10, 600, 0.125, 2.0, 900, 1500);
  CHECK(done.static_steps == 600);
  CHECK(done.fine_steps == 624);
  CHECK_FALSE(done.static_floor);
  // A static-only run (a still capture's) may stretch its one stage up to 4 x.
  CHECK(train::fitted_lengths(1e6, 10, 100, 0.1, 3.0, 2400, 0).static_steps == 9600);
  // Steps already past the floor stand.
  CHECK(train::fitted_lengths(5, 10, 300, 0.1, 3.0, 900, 1500).static_steps == 300);
  CHECK(train::fitted_lengths(5, 10, 300, 0.1, 3.0, 900, 1500).static_floor == false);
  // A static-only recipe keeps no fine stage.
  CHECK(train::fitted_lengths(70, 10, 100, 0.1, 3.0, 900, 0).fine_steps == 0);
  CHECK(train::fine_floor(1500) == 375);
  CHECK(train::fine_floor(2) == 1);
  CHECK(train::fine_floor(0) == 0);
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
  c.sh_degree = 0, c.sh_degree_auto = false;  // the SH degree chosen since the start: kept
  train::fit_schedules(c, start, 450, 3000);
  CHECK(c.iterations == 450);
  CHECK(c.densify_from == start.densify_from / 2);
  CHECK(c.densify_until == start.densify_until / 2);
  CHECK(c.fine_iterations == 3000);
  CHECK(c.fine_densify_until == start.fine_densify_until * 2);
  CHECK(c.densify_every == start.densify_every);  // as a run given these lengths: the stray points fade between prunes
  CHECK(c.lr_scale == 0.25);
  CHECK(c.sh_degree == 0);
  CHECK_FALSE(c.sh_degree_auto);
  train::fit_schedules(c, start, 900, 1500);  // back to the start: exactly its schedules
  CHECK(run::to_json(c) == [&] {
    run::TrainConfig s = start;
    s.lr_scale = 0.25;
    s.sh_degree = 0, s.sh_degree_auto = false;
    return run::to_json(s);
  }());
  train::fit_schedules(c, start, 225, 15);
  CHECK(c.densify_every == start.densify_every);
  run::TrainConfig static_only = start;
  static_only.fine_iterations = 0;
  train::fit_schedules(static_only, static_only, 100, 50);
  CHECK(static_only.fine_iterations == 0);  // no fine stage appears
}

TEST_CASE("time budget: the state round-trips through a checkpoint's JSON and refuses a broken one") {
  train::BudgetState s;
  s.fine_ratio = 2.5;
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

TEST_CASE("time budget: the Gaussian budget keeps the share of the recipe's full-budget time that the run has") {
  train::TimeEstimate e;
  e.static_seconds = 100, e.fine_seconds = 300;  // the high end: 400 s with the budget filled
  CHECK(train::gaussian_budget_share(200, e) == doctest::Approx(0.5));
  CHECK(train::gaussian_budget_share(400, e) == 1.0);
  CHECK(train::gaussian_budget_share(4000, e) == 1.0);  // never more than the recipe's budget
  CHECK(train::gaussian_budget_share(10, e) == train::kMinBudgetShare);
  CHECK(train::gaussian_budget_share(10, train::TimeEstimate{}) == 1.0);  // nothing estimated: kept
}

TEST_CASE("time budget: a plan's Gaussian budget survives the schedules' rescaling, and a given one stays given") {
  const run::TrainConfig start = run::preset_config("fast");
  run::TrainConfig c = start;
  c.budget = 7000;
  c.budget_given = false;
  train::fit_schedules(c, start, 450, 750);
  CHECK(c.budget == 7000);
  CHECK(c.iterations == 450);
  run::TrainConfig given = start;
  given.budget_given = true;
  train::fit_schedules(given, start, 450, 750);
  CHECK(given.budget_given);
  CHECK(given.budget == start.budget);
}

TEST_CASE("time budget: the Gaussian budget choice is kept in checkpoints, and older checkpoints load without it") {
  train::BudgetState s;
  s.start = run::preset_config("fast");
  s.budget_choice = {{"share", 0.5}, {"budget", 7500}};
  const train::BudgetState back = train::BudgetState::from_json(s.to_json());
  CHECK(back.budget_choice == s.budget_choice);
  nlohmann::json old = s.to_json();
  old.erase("budget_choice");
  CHECK(train::BudgetState::from_json(old).budget_choice.is_null());
}
