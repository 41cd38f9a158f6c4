// Trainer::Impl's time budget: the stages' lengths planned from measured step times (time_budget.h).
#include <cmath>
#include <cstdio>
#include <iostream>

#include "trainer_impl.h"

namespace s4d::train {

namespace {

// The static stage's steps are timed from this one on: the first compile shaders and grow buffers.
constexpr uint32_t kTimeMarkAt = 20;
// The first plan measures this many steps after the mark (the time estimate's probe); later plans
// come every tenth of the stage, at least every kMinPlanSteps.
constexpr uint32_t kFirstPlanSteps = 30, kMinPlanSteps = 10;

}  // namespace

void Trainer::Impl::plan_time_if_due(double now) {
  const double budget = config.time_budget;
  if (budget <= 0) return;
  if (!fine() && iteration < kTimeMarkAt) return;
  if (!fine() && time_plan.plans.empty() && time_plan.from_iteration < kTimeMarkAt) return mark_time(now);
  const bool first_static = !fine() && time_plan.fine_ratio == 0 && time_plan.plans.empty();
  // The fine stage's first plan comes soon: its step costs what the estimate only guessed.
  const bool first_fine = fine() && (time_plan.plans.empty() || time_plan.plans.back().at("stage") != run::stage_name(stage));
  const uint32_t steps = iteration - time_plan.from_iteration;
  const uint32_t due = first_static ? kFirstPlanSteps : first_fine ? kMinPlanSteps : std::max(kMinPlanSteps, stage_iterations() / 10);
  if (steps < due) return;
  if (iteration >= stage_iterations()) return;  // the stage ends with this step anyway
  const double per_step = (now - time_plan.from_seconds) / steps;
  if (time_plan.plans.empty()) time_plan.start = config;
  const run::TrainConfig& start = time_plan.start;
  const double fine_deadline = budget * (1 - kReserveShare);
  uint32_t length = config.iterations, fine_length = config.fine_iterations;
  bool static_floor = false, fine_held = false;
  const uint32_t budget_was = config.budget;
  if (!fine()) {
    if (first_static) {
      const TimeEstimate e = estimate_time(config, per_step, gaussians->size());
      time_plan.fine_ratio = fine_step_ratio(e, config);
      if (!config.budget_given) {  // the Gaussian budget is cut with the steps (gaussian_budget_share)
        const double share = gaussian_budget_share(fine_deadline - now + iteration * per_step, e);
        config.budget = std::max<uint32_t>(1, static_cast<uint32_t>(std::lround(share * start.budget)));
        time_plan.budget_choice = {{"share", share}, {"recipe_seconds_at_full_budget", e.static_seconds + e.fine_seconds},
                                   {"budget", config.budget}, {"start_budget", start.budget}};
      }
    }
    const StageLengths fit = fitted_lengths(fine_deadline, now, iteration, per_step, time_plan.fine_ratio,
                                            start.iterations, start.fine_iterations);
    length = fit.static_steps, static_floor = fit.static_floor, fine_held = fit.fine_floor;
    if (start.fine_iterations > 0) fine_length = fit.fine_steps;
  } else {
    fine_length = fitted_length(fine_deadline, now, iteration, per_step, start.fine_iterations);
    const uint32_t floor = fine_floor(start.fine_iterations);
    if (fine_length < floor && (double(floor) - iteration) * per_step <= kMaxFloorStretch * std::max(0.0, fine_deadline - now))
      fine_length = floor, fine_held = true;
  }
  const uint32_t was = config.iterations, fine_was = config.fine_iterations;
  fit_schedules(config, start, length, fine_length);
  mark_time(now);
  time_plan.plans.push_back({{"stage", run::stage_name(stage)}, {"iteration", iteration}, {"seconds", now},
                             {"seconds_per_step", per_step}, {"gaussians", gaussians->size()},
                             {"iterations", config.iterations}, {"fine_iterations", config.fine_iterations},
                             {"budget", config.budget}, {"static_floor", static_floor}, {"fine_floor", fine_held}});
  if (config.iterations == was && config.fine_iterations == fine_was && config.budget == budget_was) return;
  save_run_json();  // a resumed run continues with the plan
  if (!first_static && !first_fine) return;  // the later plans are in train.json
  char line[256];
  std::snprintf(line, sizeof line,
                "time budget: static stage %u steps, 4DGS stage %u, at most %u Gaussians (%.3f s per step at %s step %u "
                "with %u Gaussians; %.0f of %.0f s used)",
                config.iterations, config.fine_iterations, config.budget, per_step, run::stage_name(stage), iteration,
                gaussians->size(), now, budget);
  std::cerr << line << (static_floor || fine_held ? "; each stage is at least a quarter of the preset's, which takes longer than the budget here" : "") << "\n";
}

nlohmann::json Trainer::Impl::time_budget_json(double seconds) const {
  if (config.time_budget <= 0) return nullptr;
  return {{"given_seconds", config.time_budget}, {"took_seconds", seconds}, {"fine_step_ratio", time_plan.fine_ratio},
          {"gaussian_budget", time_plan.budget_choice}, {"plans", time_plan.plans}};
}

}  // namespace s4d::train
