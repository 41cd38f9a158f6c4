// Training checkpoints: one file holding everything a run needs to continue exactly where it
// stopped (Gaussians, Adam moments, densification statistics, iteration, random state, learning-rate
// scale), written atomically so that a crash or kill -9 leaves the previous checkpoint intact.
//
// Format: "S4DCKPT1", u64 header length, a JSON header (meta, and per array its name and float
// count, in file order), then the arrays as little-endian float32.
#pragma once
#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "s4d/model/trainable_gaussians.h"

namespace s4d::train {

struct Checkpoint {
  nlohmann::json meta;  // iteration, stage, rng state, lr scale... (owned by the trainer)
  model::HostState state;
  // Further named arrays after the Gaussians' (the deformation field and its Adam moments).
  std::vector<std::pair<std::string, std::vector<float>>> extra;
};

// Throws std::invalid_argument naming the array and index of the first non-finite value (a
// checkpoint never holds NaN), std::runtime_error when writing fails; the old file stays then.
void write_checkpoint(const std::filesystem::path& path, const Checkpoint& checkpoint);

// Throws std::runtime_error naming the file and what is wrong: missing, not a checkpoint,
// truncated, inconsistent array sizes, non-finite values.
Checkpoint read_checkpoint(const std::filesystem::path& path);

}  // namespace s4d::train
