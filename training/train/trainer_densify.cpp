// Trainer::Impl's changes to the cloud's layout: densification and opacity resets, and the split
// of the Gaussians that do not move to the end of memory.
#include <algorithm>
#include <cmath>

#include "s4d/deform/motion_split.h"
#include "s4d/train/split_state.h"
#include "trainer_impl.h"

namespace s4d::train {

void Trainer::Impl::apply_mask(const std::vector<uint32_t>& mask) {
  const deform::MotionSplit split = deform::split_by_motion(mask);
  if (!split.identity())
    gaussians = std::make_unique<model::TrainableGaussians>(ctx, gather_state(gaussians->download(), split.order), "gaussians");
  still_count = split.still_count;
}

void Trainer::Impl::update_mask() {
  const uint32_t n = gaussians->size();
  still_count = 0;  // measure with every Gaussian deformed
  std::vector<float> lo(size_t{n} * 3, INFINITY), hi(size_t{n} * 3, -INFINITY);
  const uint32_t samples = std::max<uint32_t>(2, config.motion_samples);
  for (uint32_t k = 0; k < samples; ++k) {
    const splat::GaussianParams p = deform_to(double(k) / (samples - 1));
    const std::vector<float> means = ctx.download<float>(*p[splat::Attr::means], size_t{n} * 3);
    for (size_t i = 0; i < means.size(); ++i) lo[i] = std::min(lo[i], means[i]), hi[i] = std::max(hi[i], means[i]);
  }
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

void Trainer::Impl::densify_if_due() {
  const uint32_t it = iteration;
  const uint32_t until = fine() ? config.fine_densify_until : config.densify_until;
  if (it >= until) return;
  if (it > config.densify_from && it % config.densify_every == 0) {
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
    rules.budget = config.budget;
    rules.seed = config.seed * 1000003u + it + (fine() ? 0x9E3779B9u : 0u);
    densifier.densify(*gaussians, rules);
    still_count = 0;  // the Gaussians moved in memory: the split is measured again when due
  }
  // 4DGaussians' DyNeRF setting never resets opacities in the fine stage (interval 60000).
  if (!fine() && it % config.opacity_reset_every == 0) densifier.reset_opacity(*gaussians);
}
}  // namespace s4d::train
