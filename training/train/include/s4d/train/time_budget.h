// --time-budget: a run fitted to the training time it is given. The static stage gets the share of
// the budget that the run's own time estimate gives it (time_estimate.h, the middle of its range),
// the fine stage the rest less a reserve for the closing test. Each stage's length is planned from
// the probe's step time, then re-planned every tenth of the stage from the seconds per step measured
// since the last plan (tests, densification and checkpoints included), so growth and a loaded
// machine are followed; the schedules (densification window, SH steps, tests, checkpoints) scale with
// the length, from the run's starting settings. A stage whose time is up ends at the next plan.
#pragma once
#include <cstdint>

#include <nlohmann/json.hpp>

#include "s4d/run/train_config.h"
#include "s4d/train/time_estimate.h"

namespace s4d::train {

// A stage at most this many times its starting length: more steps than the recipe's rarely pay.
inline constexpr double kMaxStretch = 4.0;
// The fine stage ends this share of the budget early, for the closing test and train.json.
inline constexpr double kReserveShare = 0.03;

// The static stage's share of the time: the estimate's split, each stage at the geometric middle
// of its low and high end. 1 without a fine stage.
double static_share(const TimeEstimate& estimate);

// The stage's length when `done` steps took until `now` and each further one takes
// `seconds_per_step`: as many as fit before `deadline`, at least `done` (the stage ends now), at
// most kMaxStretch x `start_length`.
uint32_t fitted_length(double deadline, double now, uint32_t done, double seconds_per_step, uint32_t start_length);

// `c` with the static stage `iterations` long and the fine stage `fine` long, every schedule of
// `start` (the run's starting settings) scaled to them (set_iterations, set_fine_iterations).
void fit_schedules(run::TrainConfig& c, const run::TrainConfig& start, uint32_t iterations, uint32_t fine);

// What the trainer keeps between plans (checkpoint meta and train.json "time_budget").
struct BudgetState {
  double static_share = 0;   // 0 until the first plan
  run::TrainConfig start;    // the settings the run started with
  uint32_t from_iteration = 0;  // the last plan's point in the current stage
  double from_seconds = 0;
  nlohmann::json plans = nlohmann::json::array();  // every plan: stage, iteration, seconds, s/step, Gaussians, lengths

  nlohmann::json to_json() const;
  // Throws std::runtime_error naming the field when `j` is not what to_json writes.
  static BudgetState from_json(const nlohmann::json& j);
};

}  // namespace s4d::train
