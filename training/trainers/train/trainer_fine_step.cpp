// Trainer::Impl's stage-2 step: the canonical Gaussians deformed by the field to each view's time,
// gradients summed over a batch of views.
#include <algorithm>
#include <cmath>
#include <optional>
#include <string>

#include "s4d/primitives/add.h"
#include "trainer_impl.h"

namespace s4d::train {

void Trainer::Impl::size_stage2_buffers() {
  const uint32_t n = gaussians->size();
  if (sized_for == n) return;
  deformed = deform::DeformedCloud(ctx, config.field_heads, n, gaussians->sh_coeffs());
  for (splat::Attr a : splat::kCloudAttrs)
    scratch_grad[a] = engine::Buffer(ctx, std::string("batch gradient ") + splat::attr_name(a),
                                     size_t{n} * gaussians->width(a) * 4);
  batch_stats = densifier.make_batch_scratch(n);
  sized_for = n;
}

deform::CanonicalGaussians Trainer::Impl::canonical() const {
  return deform::canonical_of(gaussians->params(-1), still_count);
}

splat::GaussianParams Trainer::Impl::record_deform(engine::Recorder& rec, double time) {
  size_stage2_buffers();
  const uint32_t n = gaussians->size();
  deform_evaluations += n - still_count;
  deform_evaluations_unmasked += n;
  const engine::StageScope timed(ctx, "field");
  return deformed.record(rec, *field, gaussians->params(active_degree()), still_count, static_cast<float>(time));
}

splat::GaussianParams Trainer::Impl::deform_to(double time) {
  engine::Recorder rec(ctx, "deform");
  const splat::GaussianParams p = record_deform(rec, time);
  ctx.run(std::move(rec));
  return p;
}

double Trainer::Impl::fine_window() const {
  const double ramp = config.fine_time_ramp * config.fine_iterations;
  return ramp > 0 ? std::min(1.0, double(iteration) / ramp) : 1.0;
}

const data::View& Trainer::Impl::next_fine_view(bool front) {
  const double window = fine_window();
  const double from = front && window < 1.0 ? window - config.fine_time_front : -1.0;
  // A band holding no view (times sparser than the band) falls back to the whole window.
  for (size_t draws = 0;; ++draws) {
    const data::View& v = *train_views[sampler.next()];
    const bool open = v.time <= window + 1e-9 || v.time <= static_window();
    if (open && (v.time >= from - 1e-9 || draws > 4 * train_views.size())) return v;
  }
}

optim::LossValue Trainer::Impl::fine_step() {
  const uint32_t batch = std::max<uint32_t>(1, config.fine_batch);
  optim::LossValue mean{};
  const bool stats = iteration < config.fine_densify_until;
  for (uint32_t b = 0; b < batch; ++b) {
    const data::View& view = next_fine_view(config.fine_time_front > 0 && (iteration * batch + b) % 2 == 0);
    const splat::Camera cam = target.load(view, frames);
    // Per view two submissions: the deformation, forward and loss; then both backwards.
    splat::GaussianParams params;
    const optim::LossValue value = forward_loss(cam, config.fine_ssim_weight, [&](engine::Recorder& rec) {
      if (b == 0) {
        const engine::StageScope timed(ctx, "field");
        field->record_zero_grads(rec);  // nothing reads them before this step's backward
      }
      return params = record_deform(rec, view.time);
    });
    if (!std::isfinite(value.loss)) return value;
    mean.loss += value.loss / batch, mean.l1 += value.l1 / batch, mean.ssim += value.ssim / batch;
    // The first view's gradients land in the cloud's gradient buffers, later ones are added to them.
    splat::GaussianGrads grads = gaussians->grads();
    if (b > 0)
      for (splat::Attr a : splat::kCloudAttrs) grads[a] = &scratch_grad[a];
    engine::Recorder rec(ctx, "backward");
    rast.record_backward(rec, params, {.v_rgb = &target.image_gradient()}, grads);
    rec.barrier();
    std::optional<engine::StageScope> timed(std::in_place, ctx, "field");
    field->record_backward(rec, canonical(), static_cast<float>(view.time), grads);
    timed.emplace(ctx, "densify");
    if (stats) densifier.record_accumulate_batch_add(rec, *gaussians, rast, batch_stats);
    rec.barrier();
    timed.emplace(ctx, "backward");  // the batch's gradient sum
    if (b > 0)
      for (splat::Attr a : splat::kCloudAttrs)
        primitives::cmd_add(rec, gaussians->grad(a), scratch_grad[a], gaussians->size() * gaussians->width(a));
    ctx.run(std::move(rec));
  }
  set_learning_rates(iteration);
  engine::Recorder rec(ctx, "fine update");
  // The batch's loss is a sum of per-view means, so the regularisers weigh `batch` times as much
  // to keep 4DGaussians' ratio (it averages over the batch).
  const float w = static_cast<float>(batch);
  std::optional<engine::StageScope> timed(std::in_place, ctx, "field");
  field->record_regularisers(rec, {config.plane_tv_weight * w, config.time_smoothness_weight * w,
                                   config.l1_time_planes_weight * w});
  timed.emplace(ctx, "densify");
  if (stats) densifier.record_accumulate_batch_end(rec, *gaussians, batch_stats);
  rec.barrier();
  timed.emplace(ctx, "adam");
  record_adam(rec);
  ctx.run(std::move(rec));
  return mean;
}
}  // namespace s4d::train
