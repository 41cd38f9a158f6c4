// Trainer::Impl's stage-1 step and what both stages' steps share: learning rates, the forward and
// loss against the view's target (view_target.h), and the Adam update.
#include <cmath>
#include <span>

#include "s4d/optim/lr_schedule.h"
#include "s4d/splat/scene_upload.h"
#include "trainer_impl.h"

namespace s4d::train {

using namespace detail;

void Trainer::Impl::set_learning_rates(uint32_t step) {
  const engine::StageScope timed(ctx, "adam");
  const double e = dataset.extent;
  const uint32_t span = stage_iterations();
  const optim::LogLinearSchedule means{config.means_lr * e, config.means_lr_final * e, span};
  const optim::LogLinearSchedule planes{config.grid_lr * e, config.grid_lr_final * e, span};
  const optim::LogLinearSchedule mlp{config.deform_lr * e, config.deform_lr_final * e, span};
  const double lrs[gCount] = {means.at(step),   config.scaling_lr, config.rotation_lr, config.opacity_lr,
                              config.sh_dc_lr,  config.sh_rest_lr, planes.at(step),    mlp.at(step)};
  for (uint32_t g = 0; g < gCount; ++g) adam.set_group(g, {.lr = lrs[g] * recovery.lr_scale}, step);
  adam.upload();
}

void Trainer::Impl::record_adam(engine::Recorder& rec) {
  const engine::StageScope timed(ctx, "adam");
  model::TrainableGaussians& g = *gaussians;
  for (splat::Attr a : {splat::Attr::means, splat::Attr::log_scales, splat::Attr::quats, splat::Attr::opacity_logits})
    g.adam(a).record(adam, rec, splat::index(a));
  g.adam(splat::Attr::sh).record_rows(adam, rec, gShDc, gShRest, g.width(splat::Attr::sh), 3);
  if (fine()) {
    field_planes.record(adam, rec, gPlanes);
    field_mlp.record(adam, rec, gMlp);
  }
}

optim::LossValue Trainer::Impl::static_step() {
  const splat::Camera cam = target.load(*static_views[sampler.next()], frames);
  const splat::GaussianParams params = gaussians->params(active_degree());
  const optim::LossValue value = forward_loss(cam, config.ssim_weight, [&](engine::Recorder&) { return params; });
  if (!std::isfinite(value.loss)) return value;
  set_learning_rates(iteration);
  // The backward, the densification statistics and Adam: the step's second and last submission.
  engine::Recorder rec(ctx, "training update");
  rast.record_backward(rec, params, {.v_rgb = &target.image_gradient()}, gaussians->grads());
  rec.barrier();
  if (iteration < config.densify_until) {
    const engine::StageScope timed(ctx, "densify");
    densifier.record_accumulate(rec, *gaussians, rast);
  }
  record_adam(rec);
  const engine::StageScope timed(ctx, "adam");
  ctx.run(std::move(rec));
  return value;
}
}  // namespace s4d::train
