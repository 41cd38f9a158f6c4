// The trainer's checkpoint: everything a run needs to continue exactly where it stopped (Gaussians,
// Adam moments, densification statistics, iteration, random state, learning-rate scale), in the run's
// checkpoint file (s4d/run/checkpoint.h: format, checksums, atomic and rotating writes). Resuming
// reads it here; what only renders reads the file through s4d_run and never sees this state.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "s4d/model/trainable_gaussians.h"
#include "s4d/run/checkpoint.h"

namespace s4d::model {

struct Checkpoint {
  nlohmann::json meta;  // iteration, stage, rng state, lr scale... (owned by the trainer)
  HostState state;
  // Further named arrays after the Gaussians' (the deformation field and its Adam moments).
  std::vector<run::NamedArray> extra;
};

// As run::write_checkpoint and run::write_checkpoint_rotating: std::invalid_argument names the array
// and index of the first non-finite value, and the old file stays.
void write_checkpoint(const std::filesystem::path& path, const Checkpoint& checkpoint);
void write_checkpoint_rotating(const std::filesystem::path& path, const std::filesystem::path& previous,
                               const Checkpoint& checkpoint, bool rotate = true);

// As run::read_checkpoint and run::read_checkpoint_or_previous.
Checkpoint read_checkpoint(const std::filesystem::path& path);

struct LoadedCheckpoint {
  Checkpoint checkpoint;
  std::filesystem::path path;  // the file it came from
  std::string newest_problem;  // empty when `path` is the newest; otherwise why the newest was passed over
};
LoadedCheckpoint read_checkpoint_or_previous(const std::filesystem::path& path, const std::filesystem::path& previous);

}  // namespace s4d::model
