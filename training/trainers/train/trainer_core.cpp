#include "s4d/train/trainer_core.h"

#include <algorithm>
#include <stdexcept>
#include <utility>

#include "s4d/engine/stage_timer.h"

namespace s4d::train {

TrainerCore::TrainerCore(engine::Context& c, TrainerParts parts)
    : ctx(c), forward_label(parts.name + " forward and loss"), train_views(std::move(parts.train_views)), test_views(std::move(parts.test_views)),
      frames(*parts.frames_of, parts.frame_cache_bytes), rast(c, parts.name + " rasterizer"), loss(c, parts.name + " loss"),
      adam(c, parts.adam_groups, parts.name + " adam"), evaluator(c),
      sampler(static_cast<uint32_t>(std::max<size_t>(train_views.size(), 1)), parts.seed), target(c, parts.name),
      background(parts.background), recovery(parts.recovery) {
  if (test_views.empty()) test_views = spread_views(train_views, kPeriodicTestViews);  // no held-out camera: report on training views
}

optim::LossValue TrainerCore::forward_loss(const splat::Camera& cam, float ssim_weight, const RecordParams& params) {
  for (;;) {  // twice at most: an overflow grows the instance buffers past the count it read
    engine::Recorder rec(ctx, forward_label);
    const splat::GaussianParams g = params(rec);
    rec.barrier();
    rast.record_forward(rec, g, cam, background);
    rec.barrier();
    {
      const engine::StageScope timed(ctx, "loss");
      loss.record(rec, rast.rgb(), target.image(), cam.width, cam.height, 3, ssim_weight, target.image_gradient());
    }
    ctx.run(std::move(rec));
    if (rast.finish_forward()) return loss.value();
  }
}

Evaluation TrainerCore::evaluate(const Evaluator::ParamsAt& params_at, const std::vector<const data::View*>& views,
                                 const std::filesystem::path& save_dir) {
  return evaluator.evaluate(rast, params_at, views, frames, background, save_dir);
}

void TrainerCore::save_checked(model::Checkpoint cp, Divergence divergence,
                               const std::function<void(const model::Checkpoint&)>& write) {
  if (divergence.found()) throw StateOutOfRange(std::move(divergence));
  write(cp);
  last_good = std::move(cp);
}

const std::vector<float>& checkpoint_array(const model::Checkpoint& cp, const std::string& name, const std::string& where) {
  for (const auto& [n, values] : cp.extra)
    if (n == name) return values;
  throw std::runtime_error(where + ": array '" + name + "' is missing");
}

}  // namespace s4d::train
