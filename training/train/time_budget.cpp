#include "s4d/train/time_budget.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace s4d::train {

double static_share(const TimeEstimate& e) {
  const double s = std::sqrt(e.static_seconds_low * e.static_seconds), f = std::sqrt(e.fine_seconds_low * e.fine_seconds);
  return f > 0 ? s / (s + f) : 1.0;
}

uint32_t fitted_length(double deadline, double now, uint32_t done, double seconds_per_step, uint32_t start_length) {
  const double cap = kMaxStretch * start_length;
  if (!(seconds_per_step > 0)) return std::max<uint32_t>(done, static_cast<uint32_t>(cap));
  const double more = std::max(0.0, std::floor((deadline - now) / seconds_per_step));
  return static_cast<uint32_t>(std::clamp(done + more, double(done), std::max(cap, double(done))));
}

void fit_schedules(run::TrainConfig& c, const run::TrainConfig& start, uint32_t iterations, uint32_t fine) {
  run::TrainConfig scaled = start;
  // Carry what a run changes itself (learning-rate halving, the data's choices) over from `c`.
  scaled.lr_scale = c.lr_scale, scaled.static_max_time = c.static_max_time, scaled.background = c.background;
  run::set_iterations(scaled, std::max<uint32_t>(1, iterations));
  if (start.fine_iterations > 0) run::set_fine_iterations(scaled, std::max<uint32_t>(1, fine));
  c = scaled;
}

nlohmann::json BudgetState::to_json() const {
  return {{"static_share", static_share}, {"start", run::to_json(start)}, {"from_iteration", from_iteration},
          {"from_seconds", from_seconds}, {"plans", plans}};
}

BudgetState BudgetState::from_json(const nlohmann::json& j) {
  BudgetState s;
  try {
    s.static_share = j.at("static_share").get<double>();
    s.start = run::config_from_json(j.at("start"), "checkpoint meta time_budget.start");
    s.from_iteration = j.at("from_iteration").get<uint32_t>();
    s.from_seconds = j.at("from_seconds").get<double>();
    s.plans = j.at("plans");
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(std::string("checkpoint meta 'time_budget': ") + e.what());
  }
  return s;
}

}  // namespace s4d::train
