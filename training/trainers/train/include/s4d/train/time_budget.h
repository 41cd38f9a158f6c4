// --time-budget: a run fitted to the training time it is given, keeping its recipe's shape. While
// the static stage runs, both stages are scaled by one factor so that the static steps left (at the
// seconds per step measured since the last plan: tests, densification and checkpoints included) and
// the fine steps (at the static step's cost times the estimate's fine-to-static ratio, time_estimate.h)
// end with the budget, less a reserve for the closing test. In the fine stage its own measured step
// fits its length to the deadline. Plans come every tenth of a stage; the schedules (densification
// window and interval, SH steps, tests, checkpoints) scale with the lengths, from the run's starting
// settings. A stage whose time is up ends at the next plan.
#pragma once
#include <cstdint>

#include <nlohmann/json.hpp>

#include "s4d/run/train_config.h"
#include "s4d/train/time_estimate.h"

namespace s4d::train {

// A stage at most this many times its starting length: more steps than the recipe's rarely pay.
inline constexpr double kMaxStretch = 4.0;
// The smallest share of the Gaussian budget a plan keeps (gaussian_budget_share).
inline constexpr double kMinBudgetShare = 0.25;
// The fine stage ends this share of the budget early, for the closing test and train.json.
inline constexpr double kReserveShare = 0.03;

// What a fine step costs in static steps, from the estimate: each stage's mean step at the
// geometric middle of its low and high end. 0 without a fine stage.
double fine_step_ratio(const TimeEstimate& estimate, const run::TrainConfig& config);

// The factor on both stages' starting lengths (`static_steps`, `fine_steps`) whose steps left end at
// `deadline`: `done` static steps were taken by `now`, each further one takes `seconds_per_step`, a
// fine one `ratio` times that. Between 0 and kMaxStretch.
double fitted_scale(double deadline, double now, uint32_t done, double seconds_per_step, double ratio,
                    uint32_t static_steps, uint32_t fine_steps);

// Each stage keeps at least this share of its starting length, however short the budget: a
// random initial cloud needs those steps for its stray points to fade before a prune, and the 4DGS
// stage needs them to reach its first densification, which prunes them. On the monocular object
// (docs/trade.md) a quarter of fast's stages pruned 5,584 random points to a few hundred; a
// 79-step static stage pruned 16 of them (2.9 dB under the front), and 225 static steps with a
// 216-step 4DGS stage, whose densification window ended before its first densification, kept
// 4,829 (1.2 dB under). The floors hold while they cost at most kMaxFloorStretch times the time
// left (at the measured step times, which overrate the steps while a random cloud is unpruned: the
// monocular object's 94 s run, whose first plans priced the quarter-length recipe at about 1.5
// times the time left, took 96 s); a budget shorter than that is met by shorter stages.
inline constexpr double kMinStageShare = 0.25;
inline constexpr double kMaxFloorStretch = 1.5;

struct StageLengths {
  uint32_t static_steps = 0, fine_steps = 0;
  bool static_floor = false, fine_floor = false;  // the stage was held at its floor (kMinStageShare)
};

// Both stages' lengths whose steps left end at `deadline` (fitted_scale's arguments): each starting
// length times fitted_scale, the static one at least `done`. The static stage stays between
// kMinStageShare of `static_steps` and `static_steps` itself (or `done`); where it is held there,
// the fine stage gets the steps that fit in the time it leaves. The fine stage is at least
// kMinStageShare of `fine_steps` (where it has any). The floors hold only while they cost at most
// kMaxFloorStretch times the time left. More static steps than the recipe's do not
// pay: the static stage fits the canonical frames, whose loss has flattened by then (fast's
// recipe), and on the monocular object a budget that stretched it to 1,142 steps left the 4DGS
// stage 795 and scored 2.0 dB under the same time spent on the recipe's 900 + 1,500
// (docs/trade.md).
StageLengths fitted_lengths(double deadline, double now, uint32_t done, double seconds_per_step, double ratio,
                            uint32_t static_steps, uint32_t fine_steps);

// The fine stage's floor: kMinStageShare of its starting length (0 without one).
uint32_t fine_floor(uint32_t fine_steps);

// The stage's length when `done` steps took until `now` and each further one takes
// `seconds_per_step`: as many as fit before `deadline`, at least `done` (the stage ends now), at
// most kMaxStretch x `start_length`.
uint32_t fitted_length(double deadline, double now, uint32_t done, double seconds_per_step, uint32_t start_length);

// `c` with the static stage `iterations` long and the fine stage `fine` long, every schedule of
// `start` (the run's starting settings) scaled to them (set_iterations, set_fine_iterations). The
// densification interval stays the start's, as in a run given those lengths: a random cloud's
// stray points need that many steps to fade between prunes. On the monocular object a budgeted run
// densifying 4 times as often ended with 2,164 Gaussians where the same lengths without a budget
// ended with 543, and scored 2.4 dB under them (docs/trade.md).
void fit_schedules(run::TrainConfig& c, const run::TrainConfig& start, uint32_t iterations, uint32_t fine);

// The share of the Gaussian budget a time budget keeps, chosen at the first plan: the seconds the
// recipe may take (the steps done included) over what it takes with the Gaussians filling the budget (the estimate's high end), between
// kMinBudgetShare and 1. Cutting the budget and the steps together rather than the steps alone: on
// the built-in scene a third of the budget took 60 % of the time for 27.30 dB, where the steps cut
// to that time give about 26.75 dB (docs/benchmarks.md, the speed/accuracy trade); a step's cost
// grows about as the Gaussians^0.5-0.65, so one factor on the budget and the rest on the steps
// splits a cut about evenly between the two. A budget the run was given (--budget) is kept.
double gaussian_budget_share(double recipe_seconds, const TimeEstimate& estimate);

// What the trainer keeps between plans (checkpoint meta and train.json "time_budget").
struct BudgetState {
  double fine_ratio = 0;     // a fine step in static steps (fine_step_ratio); 0 until the first plan
  run::TrainConfig start;    // the settings the run started with
  uint32_t from_iteration = 0;  // the last plan's point in the current stage
  double from_seconds = 0;
  nlohmann::json plans = nlohmann::json::array();  // every plan: stage, iteration, seconds, s/step, Gaussians, lengths
  nlohmann::json budget_choice;  // the first plan's Gaussian budget and its evidence; null when --budget was given

  nlohmann::json to_json() const;
  // Throws std::runtime_error naming the field when `j` is not what to_json writes.
  static BudgetState from_json(const nlohmann::json& j);
};

}  // namespace s4d::train
