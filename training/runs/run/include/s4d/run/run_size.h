// How many bytes a run writes, estimated from its settings before any work starts, so that a run
// that cannot fit refuses at once (util::require_room) instead of failing at its first checkpoint.
#pragma once
#include <cstdint>

#include "s4d/run/train_config.h"

namespace s4d::run {

// Bytes of one checkpoint holding `gaussians` Gaussians at the stored SH degree, their Adam moments
// and densification statistics, and (stage 2 runs) the deformation field with its moments.
uint64_t checkpoint_bytes(const TrainConfig& config, uint32_t gaussians);

struct RunSize {
  uint64_t least = 0;    // the first checkpoint, written twice at once (temporary + current) while rotating
  uint64_t at_budget = 0;  // checkpoints at the Gaussian budget: current, previous and the temporary, plus the PLY
  uint64_t largest_file = 0;  // the first checkpoint (the file-size limit must allow at least that)
};

// The run's sizes when it starts from `initial_gaussians` points.
RunSize run_size(const TrainConfig& config, uint32_t initial_gaussians);

}  // namespace s4d::run
