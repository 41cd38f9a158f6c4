#include "s4d/train/time_budget.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace s4d::train {

double fine_step_ratio(const TimeEstimate& e, const run::TrainConfig& c) {
  if (c.fine_iterations == 0 || c.iterations == 0) return 0;
  const double s = std::sqrt(e.static_seconds_low * e.static_seconds) / c.iterations;
  const double f = std::sqrt(e.fine_seconds_low * e.fine_seconds) / c.fine_iterations;
  return s > 0 ? f / s : 0;
}

double fitted_scale(double deadline, double now, uint32_t done, double seconds_per_step, double ratio,
                    uint32_t static_steps, uint32_t fine_steps) {
  const double unit = seconds_per_step * (static_steps + ratio * fine_steps);  // both stages at scale 1
  if (!(unit > 0)) return kMaxStretch;
  return std::clamp((deadline - now + done * seconds_per_step) / unit, 0.0, kMaxStretch);
}

uint32_t fine_floor(uint32_t fine_steps) {
  return fine_steps > 0 ? std::max<uint32_t>(1, static_cast<uint32_t>(std::lround(kMinStageShare * fine_steps))) : 0;
}

StageLengths fitted_lengths(double deadline, double now, uint32_t done, double seconds_per_step, double ratio,
                            uint32_t static_steps, uint32_t fine_steps) {
  const double f = fitted_scale(deadline, now, done, seconds_per_step, ratio, static_steps, fine_steps);
  const auto scaled = static_cast<uint32_t>(std::lround(f * static_steps));
  // A static-only run (a still capture) may stretch its one stage; a 4DGS run's static stage may not.
  const uint32_t cap = fine_steps > 0 ? std::max(done, static_steps) : std::max<uint32_t>(done, static_cast<uint32_t>(kMaxStretch * static_steps));
  // The lengths with the static stage held between `lo` and the cap; where it is held, the fine
  // stage gets the steps that fit in the time it leaves.
  auto lengths = [&](uint32_t lo) {
    StageLengths out;
    out.static_steps = std::clamp(scaled, lo, cap);
    if (fine_steps == 0) return out;
    out.fine_steps = std::max<uint32_t>(1, static_cast<uint32_t>(std::lround(f * fine_steps)));
    if (out.static_steps != scaled) {
      const double left = deadline - now - (double(out.static_steps) - done) * seconds_per_step;
      const double fine_step = seconds_per_step * ratio;
      const double fit = fine_step > 0 ? std::floor(std::max(0.0, left) / fine_step) : kMaxStretch * fine_steps;
      out.fine_steps = static_cast<uint32_t>(std::clamp(fit, 1.0, kMaxStretch * fine_steps));
    }
    return out;
  };
  const StageLengths plain = lengths(done);
  const uint32_t floor = std::max(done, static_cast<uint32_t>(std::lround(kMinStageShare * static_steps)));
  StageLengths held = lengths(floor);
  held.static_floor = scaled < floor && floor > done;
  if (held.fine_steps < fine_floor(fine_steps)) held.fine_steps = fine_floor(fine_steps), held.fine_floor = true;
  if (!held.static_floor && !held.fine_floor) return held;
  // The floors hold while they cost at most kMaxFloorStretch times the time left.
  const double cost = (double(held.static_steps) - done) * seconds_per_step + held.fine_steps * seconds_per_step * ratio;
  return cost <= kMaxFloorStretch * std::max(0.0, deadline - now) ? held : plain;
}

uint32_t fitted_length(double deadline, double now, uint32_t done, double seconds_per_step, uint32_t start_length) {
  const double cap = kMaxStretch * start_length;
  if (!(seconds_per_step > 0)) return std::max<uint32_t>(done, static_cast<uint32_t>(cap));
  const double more = std::max(0.0, std::floor((deadline - now) / seconds_per_step));
  return static_cast<uint32_t>(std::clamp(done + more, double(done), std::max(cap, double(done))));
}

double gaussian_budget_share(double recipe_seconds, const TimeEstimate& e) {
  const double full = e.static_seconds + e.fine_seconds;
  if (!(full > 0)) return 1;
  return std::clamp(recipe_seconds / full, kMinBudgetShare, 1.0);
}

void fit_schedules(run::TrainConfig& c, const run::TrainConfig& start, uint32_t iterations, uint32_t fine) {
  run::TrainConfig scaled = start;
  // Carry what a run changes itself (learning-rate halving, the data's choices) over from `c`.
  scaled.lr_scale = c.lr_scale, scaled.static_max_time = c.static_max_time, scaled.background = c.background;
  scaled.sh_degree = c.sh_degree, scaled.sh_degree_auto = c.sh_degree_auto;  // the SH choice (sh_choice.h)
  scaled.budget = c.budget, scaled.budget_given = c.budget_given;  // the first plan's (gaussian_budget_share)
  scaled.field_resolution = c.field_resolution;  // the field's fit to what moves (field_box.h)
  run::set_iterations(scaled, std::max<uint32_t>(1, iterations));
  if (start.fine_iterations > 0) run::set_fine_iterations(scaled, std::max<uint32_t>(1, fine));
  c = scaled;
}

nlohmann::json BudgetState::to_json() const {
  return {{"fine_ratio", fine_ratio}, {"start", run::to_json(start)}, {"from_iteration", from_iteration},
          {"from_seconds", from_seconds}, {"plans", plans}, {"budget_choice", budget_choice}};
}

BudgetState BudgetState::from_json(const nlohmann::json& j) {
  BudgetState s;
  try {
    s.fine_ratio = j.at("fine_ratio").get<double>();
    s.start = run::config_from_json(j.at("start"), "checkpoint meta time_budget.start");
    s.from_iteration = j.at("from_iteration").get<uint32_t>();
    s.from_seconds = j.at("from_seconds").get<double>();
    s.plans = j.at("plans");
    s.budget_choice = j.value("budget_choice", nlohmann::json());  // absent in checkpoints from before it
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(std::string("checkpoint meta 'time_budget': ") + e.what());
  }
  return s;
}

}  // namespace s4d::train
