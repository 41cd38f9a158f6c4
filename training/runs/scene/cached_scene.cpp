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
    size_t bytes = 0;
    for (splat::Attr a : splat::kCloudAttrs) bytes += g.bytes(a);
    if (used + bytes > max_bytes) {
      ctx.run(std::move(rec));  // a source may already count the recorded work as done
      break;
    }
    used += bytes;
    rec.barrier();
    Copy& c = cache_[t];  // map nodes stay put, so params may point into c
    c.params = g;
    for (splat::Attr a : splat::kCloudAttrs) {
      c.buffers[a] = engine::Buffer(ctx, std::string("cached ") + splat::attr_name(a), g.bytes(a));
      rec.copy(*g[a], c.buffers[a], g.bytes(a));
      c.params[a] = &c.buffers[a];
    }
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

size_t CachedScene::sh_style_bytes() const {
  size_t bytes = base_->sh_style_bytes();
  for (const auto& [time, copy] : cache_) bytes += copy.buffers[splat::Attr::sh].size();
  return bytes;
}

std::string CachedScene::describe() const {
  return base_->describe() + (cache_.empty() ? "" : ", " + std::to_string(cache_.size()) + " times cached");
}

}  // namespace s4d::scene
