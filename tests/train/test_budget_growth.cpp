// The Gaussian budget grown while held-out error falls (budget_growth.h): when growth is on, what
// a probe needs, the window a probe may take, what a probe's outcome does to the budget, and the
// record's round trip through run.json.
#include <cstdint>
#include <stdexcept>
#include <vector>

#include <doctest/doctest.h>

#include "s4d/run/train_config.h"
#include "s4d/train/budget_growth.h"

using namespace s4d;
using train::BudgetGrowth;
using train::BudgetProbe;

namespace {

BudgetProbe probe(uint32_t from, uint32_t to, double kept, double grown) {
  return {.stage = "static", .at_step = 400, .steps = 100, .from = from, .to = to, .demoted = 900,
          .gaussians_kept = from, .gaussians_grown = to, .psnr_kept = kept, .psnr_grown = grown, .views = 1};
}

}  // namespace

TEST_CASE("growth is on for a preset's run and off where the budget was fixed") {
  run::TrainConfig c = run::preset_config("fast");
  REQUIRE(c.budget == 15000);
  BudgetGrowth g = train::plan_budget_growth(c);
  CHECK(g.on);
  CHECK(g.ceiling == 15000);
  CHECK(g.start == 3750);  // budget_start 0.25
  CHECK(g.budget == 3750);
  CHECK(g.open());

  run::TrainConfig given = c;
  given.budget_given = true;
  g = train::plan_budget_growth(given);
  CHECK_FALSE(g.on);
  CHECK(g.budget == 15000);
  CHECK(g.why == "off: --budget fixed it");

  run::TrainConfig timed = c;
  timed.time_budget = 300;
  CHECK_FALSE(train::plan_budget_growth(timed).on);

  run::TrainConfig old = c;
  old.budget_start = 0;  // a run.json from before the growth
  g = train::plan_budget_growth(old);
  CHECK_FALSE(g.on);
  CHECK_FALSE(g.open());
  CHECK(g.budget == 15000);

  run::TrainConfig tiny = c;
  tiny.budget = 3, tiny.budget_start = 0.1;  // never a budget of 0
  CHECK(train::plan_budget_growth(tiny).start == 1);
}

TEST_CASE("budget_start outside [0, 1] is refused by name") {
  run::TrainConfig c = run::preset_config("fast");
  c.budget_start = 1.5;
  CHECK_THROWS_WITH_AS(run::validate(c, "run.json"), doctest::Contains("'budget_start'"), std::runtime_error);
  c.budget_start = -0.1;
  CHECK_THROWS_AS(run::validate(c, "run.json"), std::runtime_error);
  c.budget_start = 1;
  CHECK_NOTHROW(run::validate(c, "run.json"));
}

TEST_CASE("a probe doubles the budget up to the ceiling, and only where the budget held back a tenth of it") {
  CHECK(train::grown_budget(3750, 15000) == 7500);
  CHECK(train::grown_budget(7500, 15000) == 15000);
  CHECK(train::grown_budget(10000, 15000) == 15000);
  CHECK(train::grown_budget(3'000'000'000u, 4'000'000'000u) == 4'000'000'000u);  // no overflow
  CHECK_FALSE(train::probe_wanted(3750, 0));
  CHECK_FALSE(train::probe_wanted(3750, 374));
  CHECK(train::probe_wanted(3750, 375));
  CHECK(train::probe_wanted(1, 1));
}

TEST_CASE("a probe's window ends by the end of densification and holds no one-off step but at its last") {
  const std::vector<uint32_t> none, sh{600};
  CHECK(train::probe_window_clear(400, 100, 700, none));
  CHECK(train::probe_window_clear(600, 100, 700, none));   // ends at the last densification step
  CHECK_FALSE(train::probe_window_clear(650, 100, 700, none));
  CHECK_FALSE(train::probe_window_clear(400, 0, 700, none));
  CHECK(train::probe_window_clear(500, 100, 700, sh));      // the SH choice at its last step: after the probe
  CHECK_FALSE(train::probe_window_clear(600, 100, 700, sh));  // at its first step: the kept branch only would have it
  CHECK_FALSE(train::probe_window_clear(550, 100, 700, sh));  // inside: one branch would have it and not the other
}

TEST_CASE("a probe that gains keep_db grows the budget; one that does not stops it for good") {
  BudgetGrowth g = train::plan_budget_growth(run::preset_config("fast"));
  g.record(probe(3750, 7500, 28.25, 28.25 + train::kGrowKeepDb));
  CHECK(g.budget == 7500);
  CHECK_FALSE(g.stopped);
  CHECK(g.open());
  g.record(probe(7500, 15000, 29.96, 29.96 + train::kGrowKeepDb - 1e-3));
  CHECK(g.budget == 7500);
  CHECK(g.stopped);
  CHECK_FALSE(g.open());
  CHECK(g.why.starts_with("kept at 7500"));
  REQUIRE(g.probes.size() == 2);
  CHECK(g.probes[0]["grown"] == true);
  CHECK(g.probes[1]["grown"] == false);

  // To the ceiling: nothing is left to probe.
  BudgetGrowth up = train::plan_budget_growth(run::preset_config("fast"));
  up.record(probe(3750, 7500, 20, 21));
  up.record(probe(7500, 15000, 21, 22));
  CHECK(up.budget == 15000);
  CHECK_FALSE(up.stopped);
  CHECK_FALSE(up.open());
  CHECK(up.why.find("the ceiling") != std::string::npos);
}

TEST_CASE("the record goes through run.json unchanged, and a damaged one is refused by key") {
  BudgetGrowth g = train::plan_budget_growth(run::preset_config("fast"));
  g.record(probe(3750, 7500, 28.25, 28.91));
  const nlohmann::json j = g.json();
  CHECK(j["probes"][0]["gain_db"].get<double>() == doctest::Approx(0.66));
  CHECK(j["probes"][0]["grown"] == true);
  const BudgetGrowth back = BudgetGrowth::from_json(j);
  CHECK(back.json() == j);
  nlohmann::json broken = j;
  broken.erase("ceiling");
  CHECK_THROWS_WITH_AS(BudgetGrowth::from_json(broken), doctest::Contains("recipe.gaussian_budget"), std::runtime_error);
  broken = j;
  broken["probes"] = 3;
  CHECK_THROWS_WITH_AS(BudgetGrowth::from_json(broken), doctest::Contains("'probes'"), std::runtime_error);
}
