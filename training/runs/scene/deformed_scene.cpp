#include "s4d/scene/deformed_scene.h"

#include <string>
#include <utility>

#include "s4d/deform/motion_split.h"

namespace s4d::scene {
namespace {

constexpr uint32_t kNoSeed = 0;  // the field's initial values are replaced by the uploads

// A mask written before the trainer put still Gaussians last: they stay where the checkpoint has them.
bool still_anywhere(std::span<const uint32_t> still_mask) {
  return !still_mask.empty() && !deform::split_by_motion(still_mask).identity();
}

// The canonical SH's storage. Halves, when asked, except where still Gaussians anywhere get their
// canonical SH copied into the deformed (float) SH byte for byte.
splat::Storage canonical_sh_storage(const deform::FieldConfig& field, std::span<const uint32_t> still_mask,
                                    splat::Storage asked) {
  return (field.heads & S4D_DEFORM_HEAD_SH) != 0 && still_anywhere(still_mask) ? splat::Storage::f32 : asked;
}

}  // namespace

DeformedScene::DeformedScene(engine::Context& ctx, const io::GaussianCloud& canonical, const deform::FieldConfig& field,
                             std::span<const float> planes, std::span<const float> mlp,
                             std::span<const uint32_t> still_mask, int sh_degree, splat::Storage sh_storage)
    : ctx_(&ctx),
      canonical_(ctx, canonical, "canonical gaussians", canonical_sh_storage(field, still_mask, sh_storage)),
      field_(ctx, field, kNoSeed, "deformation field"),
      sh_degree_(sh_degree), deformed_(ctx, field.heads, canonical_.size(), canonical_.params().sh_coeffs) {
  field_.upload_planes(planes);
  field_.upload_mlp(mlp);
  const size_t n = canonical.size();
  if (!still_mask.empty()) {
    if (still_mask.size() != n)
      throw std::invalid_argument("still mask (field.static_mask): " + std::to_string(still_mask.size()) + " entries for " +
                                  std::to_string(n) + " Gaussians");
    const deform::MotionSplit split = deform::split_by_motion(still_mask);
    if (split.identity()) {
      still_count_ = split.still_count;
    } else {  // written before the trainer put still Gaussians last: keep the checkpoint's order
      for (uint32_t i = 0; i < n; ++i)
        if (still_mask[i] != 0) {
          if (still_runs_.empty() || still_runs_.back().second != i) still_runs_.emplace_back(i, i);
          still_runs_.back().second = i + 1;
        }
    }
  }
}

splat::GaussianParams DeformedScene::at(double time, const splat::Camera& camera) {
  if (last_ && last_->first == time) return last_->second;  // no submission for nothing to do
  return record_and_run(*ctx_, time, camera);
}

splat::GaussianParams DeformedScene::record(engine::Recorder& rec, double time, const splat::Camera&) {
  if (last_ && last_->first == time) return last_->second;  // nothing else writes the deformed buffers
  const splat::GaussianParams canonical = canonical_.params(sh_degree_);
  const splat::GaussianParams p = deformed_.record(rec, field_, canonical, still_count_, static_cast<float>(time));
  if (!still_runs_.empty()) {  // the old mask: still Gaussians get their canonical values back
    rec.barrier();
    const splat::GaussianBuffers<engine::Buffer> out = deformed_.outputs();  // null: head off
    for (splat::Attr a : splat::kCloudAttrs) {
      const size_t width = splat::attr_floats(a, canonical.sh_coeffs);
      for (const auto& [first, end] : still_runs_)
        if (out[a]) rec.copy(*canonical[a], *out[a], (end - first) * width * 4, first * width * 4, first * width * 4);
    }
  }
  last_.emplace(time, p);
  return p;
}

size_t DeformedScene::sh_style_bytes() const {
  return canonical_.sh_bytes() + deformed_.bytes(splat::Attr::sh);
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
