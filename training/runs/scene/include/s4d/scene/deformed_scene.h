// The 4DGS stage's scene: canonical Gaussians moved by the trained deformation field to each asked
// time by deform::DeformedCloud, the deform-to-time the trainer's evaluation runs too.
#pragma once
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "s4d/deform/deformation_field.h"
#include "s4d/deform/deformed_cloud.h"
#include "s4d/engine/buffer.h"
#include "s4d/engine/context.h"
#include "s4d/io/ply_gaussians.h"
#include "s4d/scene/scene_source.h"
#include "s4d/splat/scene_upload.h"

namespace s4d::scene {

class DeformedScene final : public SceneSource {
 public:
  // Uploads `canonical` and the field's parameters (`planes`, `mlp`: the checkpoint arrays
  // field.planes and field.mlp) and the still mask (field.static_mask) when training made one (empty: none);
  // renders at SH degree `sh_degree` (clamped to what the cloud stores). `sh_storage` f16 holds the
  // canonical SH as packed halves; a field that deforms SH reads them (deform_fwd_half) and writes
  // float deformed SH. Only a mask with still Gaussians anywhere (before the trainer put them last)
  // keeps a field's float canonical SH, which it copies into the deformed ones. Throws
  // std::invalid_argument naming the field setting or array that does not fit.
  DeformedScene(engine::Context& ctx, const io::GaussianCloud& canonical, const deform::FieldConfig& field,
                std::span<const float> planes, std::span<const float> mlp, std::span<const uint32_t> still_mask,
                int sh_degree, splat::Storage sh_storage = splat::Storage::f32);

  // Runs the field's forward pass at `time` (the camera is not read) and waits for it; the same time
  // as the last call returns the last result without running it again (a viewer orbiting a paused
  // scene).
  splat::GaussianParams record(engine::Recorder& rec, double time, const splat::Camera& camera) override;
  splat::GaussianParams at(double time, const splat::Camera& camera) override;
  uint32_t size() const override { return canonical_.size(); }
  bool dynamic() const override { return true; }
  std::string describe() const override;
  size_t sh_style_bytes() const override;

 private:
  engine::Context* ctx_;
  splat::DeviceGaussians canonical_;
  deform::DeformationField field_;
  int sh_degree_;
  deform::DeformedCloud deformed_;  // the deformed attributes of the heads that are on
  // The still Gaussians: the last still_count_, or (a checkpoint from before the trainer put them
  // last) the ranges [first, end) in still_runs_, deformed with the rest and then copied back.
  uint32_t still_count_ = 0;
  std::vector<std::pair<uint32_t, uint32_t>> still_runs_;
  std::optional<std::pair<double, splat::GaussianParams>> last_;  // the last at()'s time and result
};

}  // namespace s4d::scene
