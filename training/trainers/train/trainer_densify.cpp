// Trainer::Impl's changes to the cloud's layout: densification and opacity resets, and the split
// of the Gaussians that do not move to the end of memory.
#include <algorithm>
#include <cmath>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "s4d/deform/motion_split.h"
#include "s4d/train/prune_floor.h"
#include "s4d/train/split_state.h"
#include "trainer_impl.h"

namespace s4d::train {

void Trainer::Impl::apply_mask(const std::vector<uint32_t>& mask) {
  const deform::MotionSplit split = deform::split_by_motion(mask);
  if (!split.identity())
    gaussians = std::make_unique<model::TrainableGaussians>(ctx, gather_state(gaussians->download(), split.order), "gaussians");
  still_count = split.still_count;
}

void Trainer::Impl::path_bounds(std::vector<float>& lo, std::vector<float>& hi) {
  const uint32_t n = gaussians->size();
  const uint32_t still = still_count;
  still_count = 0;  // measure with every Gaussian deformed
  lo.assign(size_t{n} * 3, INFINITY), hi.assign(size_t{n} * 3, -INFINITY);
  const uint32_t samples = std::max<uint32_t>(2, config.motion_samples);
  for (uint32_t k = 0; k < samples; ++k) {
    const splat::GaussianParams p = deform_to(double(k) / (samples - 1));
    const std::vector<float> means = ctx.download<float>(*p[splat::Attr::means], size_t{n} * 3);
    for (size_t i = 0; i < means.size(); ++i) lo[i] = std::min(lo[i], means[i]), hi[i] = std::max(hi[i], means[i]);
  }
  still_count = still;
}

void Trainer::Impl::update_mask() {
  const uint32_t n = gaussians->size();
  std::vector<float> lo, hi;
  path_bounds(lo, hi);
  const double limit = config.static_motion * dataset.extent;
  std::vector<uint32_t> mask(n);
  for (uint32_t i = 0; i < n; ++i) {
    const double dx = hi[i * 3] - lo[i * 3], dy = hi[i * 3 + 1] - lo[i * 3 + 1], dz = hi[i * 3 + 2] - lo[i * 3 + 2];
    mask[i] = std::sqrt(dx * dx + dy * dy + dz * dz) < limit ? 1u : 0u;
  }
  apply_mask(mask);
}

bool Trainer::Impl::mask_due() const {
  return fine() && config.static_motion > 0 && head(S4D_DEFORM_HEAD_POS) && iteration >= config.fine_densify_until &&
         (iteration - config.fine_densify_until) % std::max<uint32_t>(1, config.motion_every) == 0;
}

namespace {

// 5832 -> "5,832": counts in messages read at a glance.
std::string thousands(uint64_t v) {
  const std::string digits = std::to_string(v);
  std::string out;
  for (size_t i = 0; i < digits.size(); ++i) {
    if (i > 0 && (digits.size() - i) % 3 == 0) out += ',';
    out += digits[i];
  }
  return out;
}

std::vector<float> opacities(engine::Context& ctx, const model::TrainableGaussians& g) {
  std::vector<float> o = ctx.download<float>(g.param(splat::Attr::opacity_logits), g.size());
  for (float& v : o) v = 1.0f / (1.0f + std::exp(-v));
  return o;
}

}  // namespace

densify::DensifyRules Trainer::Impl::prune_rules_with_floor(densify::DensifyRules rules, const std::string& when) {
  if (!rules.prune) return rules;
  if (prune_floor_why.is_null()) {
    const PruneFloor f = measure_prune_floor(frames, train_views, dataset.background, config.budget);
    prune_floor = f.count;
    prune_floor_why = f.json();
  }
  const uint32_t n = gaussians->size();
  const float lowered = floor_opacity(opacities(ctx, *gaussians), rules.min_opacity, prune_floor);
  if (lowered < rules.min_opacity) {
    // The size rules are off too: the floor is a promise about the count.
    rules.min_opacity = lowered;
    rules.max_screen_radius = 0;
    rules.max_world_scale = 0;
    std::cerr << "densify (" << when << "): pruning at opacity " << config.min_opacity << " would leave fewer than "
              << thousands(prune_floor) << " of " << thousands(n) << " Gaussians, the floor set by the visible content ("
              << thousands(static_cast<uint64_t>(prune_floor_why["content_pixels_per_view"].get<double>()))
              << " content pixels per view / " << kPixelsPerGaussian << "); keeping the " << thousands(std::min(prune_floor, n))
              << " most opaque (opacity >= " << lowered << ")\n";
  }
  return rules;
}

void Trainer::Impl::log_densify(const std::string& when, const densify::DensifyResult& r, uint32_t below_opacity,
                                float min_opacity) {
  densify_log.push_back({{"stage", run::stage_name(stage)}, {"iteration", iteration}, {"event", "densify"},
                         {"before", r.before}, {"cloned", r.cloned}, {"split", r.split}, {"pruned", r.pruned},
                         {"demoted", r.demoted}, {"after", r.after}, {"floor", prune_floor}});
  // A prune that removes most of the model says why.
  if (r.before > 0 && r.pruned * 2 > r.before)
    std::cerr << "densify (" << when << "): pruned " << thousands(r.pruned) << " of " << thousands(r.before) << " Gaussians ("
              << (100 * r.pruned / r.before) << " %): " << thousands(below_opacity) << " had opacity below "
              << min_opacity << ", the rest were too large on screen or in the world; "
              << thousands(r.after) << " left\n";
}

densify::DensifyResult Trainer::Impl::densify_now(const std::string& when, uint32_t budget) {
  const uint32_t it = iteration;
  densify::DensifyRules rules;
  // A batch's statistic is the norm of a sum over its views where 4DGaussians sums gradients of
  // the batch mean: the same test is `batch` times the threshold.
  rules.grad_threshold = config.grad_threshold * (fine() ? static_cast<float>(std::max<uint32_t>(1, config.fine_batch)) : 1.0f);
  rules.dense_scale = static_cast<float>(config.percent_dense * dataset.extent);
  rules.min_opacity = config.min_opacity;
  if (!fine() && it > config.opacity_reset_every) {  // graphdeco: size pruning only after the first reset
    rules.max_screen_radius = config.max_screen_radius;
    rules.max_world_scale = static_cast<float>(0.1 * dataset.extent);
  }
  rules.budget = budget;
  rules.seed = config.seed * 1000003u + it + (fine() ? 0x9E3779B9u : 0u);
  rules = prune_rules_with_floor(rules, when);
  const std::vector<float> o = opacities(ctx, *gaussians);
  const auto below = static_cast<uint32_t>(std::count_if(o.begin(), o.end(), [&](float v) { return v < rules.min_opacity; }));
  const densify::DensifyResult r = densifier.densify(*gaussians, rules);
  log_densify(when, r, below, rules.min_opacity);
  still_count = 0;  // the Gaussians moved in memory: the split is measured again when due
  seed_missing_content(when);
  return r;
}

void Trainer::Impl::densify_if_due(double seconds) {
  const uint32_t it = iteration;
  const uint32_t until = fine() ? config.fine_densify_until : config.densify_until;
  // Frames the fine stage's time window opens after densification ends still get seeds for what
  // they show first.
  if (it >= until) {
    if (fine() && fine_window() < 1.0 && it % config.densify_every == 0)
      seed_missing_content(std::string(run::stage_name(stage)) + " stage, iteration " + std::to_string(it));
    return;
  }
  if (it > config.densify_from && it % config.densify_every == 0) {
    // The state before, in case the budget holds this densification back (budget_growth.h).
    std::optional<model::Checkpoint> before;
    if (budget_probe_possible()) before = snapshot(seconds);
    const densify::DensifyResult r = densify_now(std::string(run::stage_name(stage)) + " stage, iteration " + std::to_string(it),
                                                 densify_budget());
    if (before) start_budget_probe(std::move(*before), r);
  }
  // 4DGaussians' DyNeRF setting never resets opacities in the fine stage (interval 60000). A reset
  // within the stage's last densification interval would leave no steps to recover: the static
  // model would end nearly transparent (`default`'s 3,000-step stage resets at its last step).
  if (!fine() && it % config.opacity_reset_every == 0 && it + config.densify_every <= config.iterations)
    densifier.reset_opacity(*gaussians);
}
}  // namespace s4d::train
