#include "s4d/run/run_size.h"

#include <algorithm>

#include "s4d/deform/field_config.h"
#include "s4d_deform.h"

namespace s4d::run {

namespace {

// A Gaussian's parameters: means 3, log-scales 3, quaternions 4, opacity 1, SH at the stored degree.
uint64_t parameter_floats(const TrainConfig& config) {
  return 11 + 3ull * static_cast<uint64_t>((config.sh_degree + 1) * (config.sh_degree + 1));
}

}  // namespace

uint64_t checkpoint_bytes(const TrainConfig& config, uint32_t gaussians) {
  // The parameters and their two Adam moments, the three densification statistics; the 4DGS stage
  // adds the static-split mask.
  const uint64_t per_gaussian = 3 * parameter_floats(config) + 3 + (config.fine_iterations > 0 ? 1 : 0);
  uint64_t floats = per_gaussian * gaussians;
  if (config.fine_iterations > 0) {
    const gpu::DeformShape shape = deform::deform_shape(field_config(config, {0, 0, 0}, {1, 1, 1}));
    floats += 3ull * (gpu::deform_planes_total(shape) + uint64_t{gpu::deform_mlp_total(shape)});
  }
  // And the JSON header: measured 8.7 KB on 12 views, most of it the view sampler's order.
  return 4 * floats + 65536;
}

RunSize run_size(const TrainConfig& config, uint32_t initial_gaussians) {
  RunSize s;
  const uint32_t start = std::min(initial_gaussians, config.budget);
  s.largest_file = checkpoint_bytes(config, start);
  s.least = 2 * s.largest_file;
  s.at_budget = 3 * checkpoint_bytes(config, config.budget) + 4 * parameter_floats(config) * config.budget;
  return s;
}

}  // namespace s4d::run
