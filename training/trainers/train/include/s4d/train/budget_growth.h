// The Gaussian budget grown while held-out error still falls (TrainConfig::budget_start). A run
// starts densifying to a share of its preset's budget (the ceiling). When a densification is held
// back by the budget (its demoted candidates are at least kGrowMinDemand of it), the run measures
// what more Gaussians buy with a paired probe: it trains the next densify_every steps at the budget
// (the kept branch), renders the held-out views, goes back to the densification, does it again at
// twice the budget (the grown branch), trains the same steps on the same views and renders them
// again. The grown branch is kept when it scores kGrowKeepDb more; otherwise the run goes on from
// the kept branch and the budget stops growing. Both branches train the same steps from the same
// state, so the difference is what the extra Gaussians bought, not what more training buys (the
// held-out PSNR of a single run rises with its steps either way). Written to train.json
// dataset.recipe.gaussian_budget.
#pragma once
#include <cstdint>
#include <span>
#include <string>

#include <nlohmann/json.hpp>

#include "s4d/run/train_config.h"

namespace s4d::train {

// Held-out PSNR the grown branch must add for the budget to grow. Two branches at the same budget
// differ by at most 1.6e-4 dB (the built-in scene's static stage, 4 seeds), so a gain is the Gaussians'.
// On the built-in scene 7,500 -> 15,000 Gaussians gained 0.10 dB in a 100-step probe and 0.62 dB at
// the end of `fast`: 0.05 dB stops growth where a doubling would buy about 0.3 dB in the end.
constexpr double kGrowKeepDb = 0.05;
// A densification probes only when the budget held back at least this share of it: fewer demoted
// candidates could not show what a larger budget buys.
constexpr double kGrowMinDemand = 0.1;
// Each growth doubles the budget (up to the ceiling): from a quarter, at most two probes.
constexpr uint32_t kGrowFactor = 2;

// One probe's evidence.
struct BudgetProbe {
  std::string stage;
  uint32_t at_step = 0;          // the densification's iteration in its stage
  uint32_t steps = 0;            // steps each branch trained
  uint32_t from = 0, to = 0;     // the budget kept and the budget tried
  uint32_t demoted = 0;          // candidates the kept budget held back
  uint32_t gaussians_kept = 0, gaussians_grown = 0;  // at the end of each branch
  double psnr_kept = 0, psnr_grown = 0;              // held-out PSNR (dB) at the end of each branch
  uint32_t views = 0;
  double seconds = 0;    // the kept branch's steps and test: what the probe cost the run
  bool held_out = true;  // false: the dataset holds no test view out, so training views were used
  bool grown() const { return psnr_grown - psnr_kept >= kGrowKeepDb; }
  nlohmann::json json() const;
};

// The run's growth: on or off (and why), the ceiling, the budget so far and every probe.
struct BudgetGrowth {
  bool on = false;
  bool stopped = false;  // a probe found no gain: the budget stays
  uint32_t ceiling = 0, start = 0, budget = 0;
  nlohmann::json probes = nlohmann::json::array();  // each probe's json(), in order
  std::string why;
  nlohmann::json json() const;
  static BudgetGrowth from_json(const nlohmann::json& j);  // std::runtime_error naming the key
  // Whether the budget may still grow: on, not stopped and below the ceiling.
  bool open() const { return on && !stopped && budget < ceiling; }
  // Records a finished probe: the budget grows to its `to`, or stops.
  void record(const BudgetProbe& probe);
};

// A new run's growth: on when budget_start > 0 and neither --budget nor a time budget fixed the
// budget (the time budget chooses its own: time_budget.h).
BudgetGrowth plan_budget_growth(const run::TrainConfig& config);

// The budget tried after `budget`: kGrowFactor times it, at most the ceiling.
uint32_t grown_budget(uint32_t budget, uint32_t ceiling);

// Whether a densification that held back `demoted` candidates at `budget` is worth a probe.
bool probe_wanted(uint32_t budget, uint32_t demoted);

// Whether a probe's branches, steps (at, at + length] of a stage, fit before `until` (the end of
// the stage's densification) and hold none of `events` in [at, at + length): one-off steps that
// change the model or settings the restore does not bring back (the SH choice, the field's fit), or
// write a checkpoint mid-probe. One at `at` would run in the kept branch after the state before was
// taken; one at the last step runs after the probe has decided.
bool probe_window_clear(uint32_t at, uint32_t length, uint32_t until, std::span<const uint32_t> events);

}  // namespace s4d::train
