#include "s4d/scene/deformed_scene.h"

#include <iterator>
#include <string>
#include <utility>

#include "s4d/deform/static_split.h"

namespace s4d::scene {
namespace {

constexpr uint32_t kNoSeed = 0;  // the field's initial values are replaced by the uploads

engine::Buffer head_buffer(engine::Context& ctx, uint32_t heads, uint32_t bit, const std::string& name, size_t floats) {
  return (heads & bit) ? engine::Buffer(ctx, "deformed " + name, floats * 4) : engine::Buffer();
}

}  // namespace

DeformedScene::DeformedScene(engine::Context& ctx, const io::GaussianCloud& canonical, const deform::FieldConfig& field,
                             std::span<const float> planes, std::span<const float> mlp,
                             std::span<const uint32_t> static_mask, int sh_degree)
    : ctx_(&ctx), canonical_(ctx, canonical, "canonical gaussians"), field_(ctx, field, kNoSeed, "deformation field"),
      sh_degree_(sh_degree) {
  field_.upload_planes(planes);
  field_.upload_mlp(mlp);
  const size_t n = canonical.size();
  if (!static_mask.empty()) {
    if (static_mask.size() != n)
      throw std::invalid_argument("static mask: " + std::to_string(static_mask.size()) + " entries for " +
                                  std::to_string(n) + " Gaussians");
    const deform::StaticSplit split = deform::split_static(static_mask);
    if (split.identity()) {
      static_count_ = split.static_count;
    } else {  // written before the trainer put static Gaussians last: keep the checkpoint's order
      for (uint32_t i = 0; i < n; ++i)
        if (static_mask[i] != 0) {
          if (static_runs_.empty() || static_runs_.back().second != i) static_runs_.emplace_back(i, i);
          static_runs_.back().second = i + 1;
        }
    }
  }
  means_ = head_buffer(ctx, field.heads, S4D_DEFORM_HEAD_POS, "means", n * 3);
  log_scales_ = head_buffer(ctx, field.heads, S4D_DEFORM_HEAD_SCALES, "log_scales", n * 3);
  quats_ = head_buffer(ctx, field.heads, S4D_DEFORM_HEAD_ROTATIONS, "quats", n * 4);
  opacity_logits_ = head_buffer(ctx, field.heads, S4D_DEFORM_HEAD_OPACITY, "opacity_logits", n);
  sh_ = head_buffer(ctx, field.heads, S4D_DEFORM_HEAD_SH, "sh", canonical.sh.size());
}

splat::GaussianParams DeformedScene::at(double time, const splat::Camera&) {
  if (last_ && last_->first == time) return last_->second;  // nothing else writes the deformed buffers
  splat::GaussianParams p = canonical_.params(sh_degree_);
  const uint32_t heads = field_.config().heads;
  auto out = [&](uint32_t bit, engine::Buffer& b) { return (heads & bit) ? &b : nullptr; };
  const deform::DeformedGaussians deformed{out(S4D_DEFORM_HEAD_POS, means_), out(S4D_DEFORM_HEAD_SCALES, log_scales_),
                                           out(S4D_DEFORM_HEAD_ROTATIONS, quats_),
                                           out(S4D_DEFORM_HEAD_OPACITY, opacity_logits_), out(S4D_DEFORM_HEAD_SH, sh_)};
  engine::Recorder rec(*ctx_, "deform to time");
  field_.record_forward(rec,
                        {.means = p.means,
                         .log_scales = p.log_scales,
                         .quats = p.quats,
                         .opacity_logits = p.opacity_logits,
                         .sh = p.sh,
                         .count = p.count,
                         .static_count = static_count_,
                         .sh_coeffs = p.sh_coeffs},
                        static_cast<float>(time), deformed);
  if (!static_runs_.empty()) {  // the old mask: static Gaussians get their canonical values back
    rec.barrier();
    const std::pair<const engine::Buffer*, engine::Buffer*> pairs[] = {  // canonical, deformed (null: head off)
        {p.means, deformed.means}, {p.log_scales, deformed.log_scales}, {p.quats, deformed.quats},
        {p.opacity_logits, deformed.opacity_logits}, {p.sh, deformed.sh}};
    const size_t widths[] = {3, 3, 4, 1, size_t{3} * p.sh_coeffs};
    for (size_t h = 0; h < std::size(pairs); ++h)
      for (const auto& [first, end] : static_runs_)
        if (pairs[h].second)
          rec.copy(*pairs[h].first, *pairs[h].second, (end - first) * widths[h] * 4, first * widths[h] * 4,
                   first * widths[h] * 4);
  }
  ctx_->run(std::move(rec));
  if (deformed.means) p.means = deformed.means;
  if (deformed.log_scales) p.log_scales = deformed.log_scales;
  if (deformed.quats) p.quats = deformed.quats;
  if (deformed.opacity_logits) p.opacity_logits = deformed.opacity_logits;
  if (deformed.sh) p.sh = deformed.sh;
  last_.emplace(time, p);
  return p;
}

std::string DeformedScene::describe() const {
  std::string heads;
  for (const auto& [bit, name] : {std::pair{S4D_DEFORM_HEAD_POS, "position"}, {S4D_DEFORM_HEAD_SCALES, "scales"},
                                  {S4D_DEFORM_HEAD_ROTATIONS, "rotations"}, {S4D_DEFORM_HEAD_OPACITY, "opacity"},
                                  {S4D_DEFORM_HEAD_SH, "SH"}})
    if (field_.config().heads & bit) heads += (heads.empty() ? "" : ", ") + std::string(name);
  return "4dgs: " + std::to_string(canonical_.size()) + " canonical Gaussians, deformation field heads " + heads +
         " (SH degree " + std::to_string(canonical_.params(sh_degree_).sh_degree) + ")";
}

}  // namespace s4d::scene
