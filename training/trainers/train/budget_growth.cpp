#include "s4d/train/budget_growth.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace s4d::train {

nlohmann::json BudgetProbe::json() const {
  return {{"stage", stage},           {"at_step", at_step},       {"steps", steps},
          {"from", from},             {"to", to},                 {"demoted", demoted},
          {"gaussians_kept", gaussians_kept}, {"gaussians_grown", gaussians_grown},
          {"psnr_kept", psnr_kept},   {"psnr_grown", psnr_grown}, {"gain_db", psnr_grown - psnr_kept},
          {"views", views},           {"seconds", seconds},       {"held_out", held_out},     {"grown", grown()}};
}

nlohmann::json BudgetGrowth::json() const {
  return {{"grows", on},         {"stopped", stopped},  {"ceiling", ceiling},    {"start", start},
          {"budget", budget},    {"keep_db", kGrowKeepDb}, {"min_demand", kGrowMinDemand},
          {"probes", probes},    {"why", why}};
}

BudgetGrowth BudgetGrowth::from_json(const nlohmann::json& j) {
  BudgetGrowth g;
  try {
    g.on = j.at("grows").get<bool>();
    g.stopped = j.at("stopped").get<bool>();
    g.ceiling = j.at("ceiling").get<uint32_t>();
    g.start = j.at("start").get<uint32_t>();
    g.budget = j.at("budget").get<uint32_t>();
    g.why = j.at("why").get<std::string>();
    g.probes = j.at("probes");
    if (!g.probes.is_array()) throw std::runtime_error("recipe.gaussian_budget: 'probes' is not an array");
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(std::string("recipe.gaussian_budget: ") + e.what());
  }
  return g;
}

void BudgetGrowth::record(const BudgetProbe& probe) {
  probes.push_back(probe.json());
  if (probe.grown()) {
    budget = probe.to;
    why = "grown to " + std::to_string(budget) + ": the held-out PSNR rose " + std::to_string(probe.psnr_grown - probe.psnr_kept) +
          " dB with the larger budget";
    if (budget >= ceiling) why += "; the ceiling (the preset's budget) is reached";
  } else {
    stopped = true;
    why = "kept at " + std::to_string(budget) + ": twice the budget bought " + std::to_string(probe.psnr_grown - probe.psnr_kept) +
          " dB on the held-out views, under keep_db";
  }
}

BudgetGrowth plan_budget_growth(const run::TrainConfig& c) {
  BudgetGrowth g;
  g.ceiling = g.budget = g.start = c.budget;
  if (c.budget_start <= 0) {
    g.why = "off: budget_start is 0; the budget is the setting's";
  } else if (c.budget_given) {
    g.why = "off: --budget fixed it";
  } else if (c.time_budget > 0) {
    g.why = "off: the time budget chooses the Gaussian budget";
  } else {
    g.on = true;
    g.start = g.budget = std::max<uint32_t>(1, static_cast<uint32_t>(std::lround(c.budget * c.budget_start)));
    g.why = "starts at " + std::to_string(g.start) + " (budget_start of the preset's " + std::to_string(c.budget) +
            "); grows while a probe's held-out PSNR rises";
  }
  return g;
}

uint32_t grown_budget(uint32_t budget, uint32_t ceiling) {
  return static_cast<uint32_t>(std::min<uint64_t>(ceiling, uint64_t{budget} * kGrowFactor));
}

bool probe_wanted(uint32_t budget, uint32_t demoted) { return demoted > 0 && demoted >= kGrowMinDemand * budget; }

bool probe_window_clear(uint32_t at, uint32_t length, uint32_t until, std::span<const uint32_t> events) {
  if (length == 0 || uint64_t{at} + length > until) return false;
  return std::none_of(events.begin(), events.end(), [&](uint32_t e) { return e >= at && e < at + length; });
}

}  // namespace s4d::train
