// Trainer::Impl's growth of the Gaussian budget by paired probes (budget_growth.h).
#include <algorithm>
#include <cstdio>
#include <iostream>
#include <vector>

#include "s4d/train/field_box.h"
#include "s4d/train/sh_choice.h"
#include "trainer_impl.h"

namespace s4d::train {

uint32_t Trainer::Impl::densify_budget() const {
  if (probe.phase == GrowthProbe::grown) return probe.record.to;
  return growth.on ? growth.budget : config.budget;
}

bool Trainer::Impl::budget_probe_possible() const {
  if (!growth.open() || probe.phase != GrowthProbe::none || probe_held) return false;
  // A densification turns each Gaussian into at most two: below half the budget none is held back.
  if (uint64_t{gaussians->size()} * 2 <= growth.budget) return false;
  // One-off steps the branches must not differ by (probe_window_clear).
  std::vector<uint32_t> events;
  if (config.sh_degree_auto && config.sh_degree > 0) {
    const uint32_t s = sh_choice_step(config);  // counted over both stages
    if (!fine() && s <= config.iterations) events.push_back(s);
    if (fine() && s > config.iterations) events.push_back(s - config.iterations);
  }
  if (fine() && !field_fitted && field_fit_step(config) > 0) events.push_back(field_fit_step(config));
  const uint32_t every = std::max<uint32_t>(1, config.checkpoint_every);
  events.push_back((iteration / every + 1) * every);  // the next checkpoint
  const uint32_t until = fine() ? config.fine_densify_until : config.densify_until;
  return probe_window_clear(iteration, config.densify_every, std::min(until, stage_iterations()), events);
}

void Trainer::Impl::start_budget_probe(model::Checkpoint before, const densify::DensifyResult& r) {
  if (!probe_wanted(growth.budget, r.demoted)) return;
  probe.phase = GrowthProbe::kept;
  probe.before = std::move(before);
  probe.record = {.stage = run::stage_name(stage),
                  .at_step = iteration,
                  .steps = config.densify_every,
                  .from = growth.budget,
                  .to = grown_budget(growth.budget, growth.ceiling),
                  .demoted = r.demoted};
}

void Trainer::Impl::budget_probe_step(double seconds) {
  if (probe.phase == GrowthProbe::none || iteration != probe.record.at_step + probe.record.steps) return;
  const auto [views, held_out] = stage_held_out_views();
  const double psnr = evaluate(views).psnr;
  BudgetProbe& rec = probe.record;
  if (probe.phase == GrowthProbe::kept) {
    rec.psnr_kept = psnr, rec.gaussians_kept = gaussians->size();
    rec.views = static_cast<uint32_t>(views.size());
    rec.held_out = held_out;
    rec.seconds = seconds - probe.before.meta.at("seconds").get<double>();
    probe.kept_end = snapshot(seconds);
    restore(probe.before);  // the densification's iteration, sampler and statistics
    probe.phase = GrowthProbe::grown;  // densify_budget() is now rec.to
    return;
  }
  rec.psnr_grown = psnr, rec.gaussians_grown = gaussians->size();
  if (!rec.grown()) restore(probe.kept_end);
  growth.record(rec);
  const BudgetProbe done = rec;
  probe = {};
  facts["recipe"]["gaussian_budget"] = growth.json();
  save_run_json();  // a resumed run densifies to the budget decided

  char line[320];
  std::snprintf(line, sizeof line,
                "Gaussian budget %s %u: %u Gaussians scored %.2f dB on %u %s views after %u steps, %u scored %.2f dB "
                "(budget %u); the budget grows on %.2f dB",
                done.grown() ? "grown to" : "kept at", growth.budget, done.gaussians_grown, done.psnr_grown, done.views,
                done.held_out ? "held-out" : "training", done.steps, done.gaussians_kept, done.psnr_kept, done.from, kGrowKeepDb);
  std::cerr << "densify (" << done.stage << " stage, iteration " << iteration << "): " << line << "\n";
}

void Trainer::Impl::abandon_budget_probe(double seconds) {
  if (probe.phase == GrowthProbe::none) return;
  const model::Checkpoint before = std::move(probe.before);
  probe = {};
  restore(before);
  probe_held = true;  // the densification again, at the budget decided, without a new probe
  densify_if_due(seconds);
  probe_held = false;
  std::cerr << "Gaussian budget probe at " << run::stage_name(stage) << " iteration " << iteration
            << " left undecided (the run stopped); the run continues from that densification at the budget "
            << growth.budget << "\n";
}

}  // namespace s4d::train
