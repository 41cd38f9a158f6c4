#include "s4d/scene/cached_scene.h"

#include "s4d/engine/recorder.h"

namespace s4d::scene {

CachedScene::CachedScene(engine::Context& ctx, std::unique_ptr<SceneSource> base, const std::vector<double>& times,
                         size_t max_bytes)
    : ctx_(&ctx), base_(std::move(base)) {
  if (!base_->dynamic()) return;
  size_t used = 0;
  const splat::Camera unused{};
  for (double t : times) {
    if (cache_.count(t)) continue;
    engine::Recorder rec(ctx, "cache scene");  // the base's work and the copies: one submission
    const splat::GaussianParams g = base_->record(rec, t, unused);
    const size_t n = g.count;
    const size_t bytes = n * (3 + 3 + 4 + 1 + size_t{g.sh_coeffs} * 3) * 4;
    if (used + bytes > max_bytes) {
      ctx.run(std::move(rec));  // a source may already count the recorded work as done
      break;
    }
    used += bytes;
    rec.barrier();
    Copy& c = cache_[t];  // map nodes stay put, so params may point into c
    auto copy = [&](const engine::Buffer* src, engine::Buffer& dst, size_t floats, const char* what) {
      dst = engine::Buffer(ctx, std::string("cached ") + what, floats * 4);
      rec.copy(*src, dst, floats * 4);
      return &dst;
    };
    c.params = g;
    c.params.means = copy(g.means, c.means, n * 3, "means");
    c.params.log_scales = copy(g.log_scales, c.log_scales, n * 3, "log scales");
    c.params.quats = copy(g.quats, c.quats, n * 4, "quats");
    c.params.opacity_logits = copy(g.opacity_logits, c.opacity_logits, n, "opacity");
    c.params.sh = copy(g.sh, c.sh, n * g.sh_coeffs * 3, "sh");
    ctx.run(std::move(rec));
  }
}

splat::GaussianParams CachedScene::record(engine::Recorder& rec, double time, const splat::Camera& camera) {
  const auto it = cache_.find(time);
  return it == cache_.end() ? base_->record(rec, time, camera) : it->second.params;
}

splat::GaussianParams CachedScene::at(double time, const splat::Camera& camera) {
  const auto it = cache_.find(time);
  return it == cache_.end() ? base_->at(time, camera) : it->second.params;
}

std::string CachedScene::describe() const {
  return base_->describe() + (cache_.empty() ? "" : ", " + std::to_string(cache_.size()) + " times cached");
}

}  // namespace s4d::scene
