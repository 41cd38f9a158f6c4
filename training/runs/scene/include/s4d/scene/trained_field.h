// The 4DGS stage's result as a run's checkpoint holds it (s4d/run/checkpoint.h): the
// canonical Gaussians, the deformation field's parameters (arrays field.planes and field.mlp) and
// its bounds (meta aabb_min / aabb_max) and resolution (meta field_resolution, where written). All
// come from the one file, so they always belong together.
#pragma once
#include <cstdint>
#include <filesystem>
#include <vector>

#include "s4d/deform/field_config.h"
#include "s4d/io/ply_gaussians.h"
#include "s4d/run/train_config.h"

namespace s4d::scene {

struct TrainedField {
  io::GaussianCloud canonical;
  deform::FieldConfig field;
  std::vector<float> planes, mlp;
  std::vector<uint32_t> still_mask;  // empty, or per Gaussian non-zero = skips the field (--static-motion)
  uint32_t fine_iteration = 0;  // fine-stage iterations the checkpoint has done
};

// Reads `checkpoint` of the run at `run_root` trained with `config`. Throws std::runtime_error
// naming the file and what is missing or wrong: the checkpoint itself (read_checkpoint's errors), a
// checkpoint still in the static stage (the 4DGS stage has not started: finish with --resume), meta
// without stage / iteration / aabb_min / aabb_max, the arrays field.planes or field.mlp missing or
// of another size than the field `config` describes, or settings the field kernels cannot run.
TrainedField read_trained_field(const std::filesystem::path& checkpoint, const run::TrainConfig& config,
                                const std::filesystem::path& run_root);

}  // namespace s4d::scene
