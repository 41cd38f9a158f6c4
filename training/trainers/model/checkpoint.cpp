#include "s4d/model/checkpoint.h"

#include <utility>

namespace s4d::model {

namespace {

// The state's arrays in the file's order (run::trainer_array_names()).
run::CheckpointRef file_of(const Checkpoint& cp) {
  run::CheckpointRef ref{cp.meta, cp.state.cloud, {}, cp.extra};
  for (Attr a : splat::kCloudAttrs) {
    ref.trainer.push_back(&cp.state.m[a]);
    ref.trainer.push_back(&cp.state.v[a]);
  }
  for (const std::vector<float>& s : cp.state.stats) ref.trainer.push_back(&s);
  return ref;
}

Checkpoint from_file(run::Checkpoint&& file) {
  Checkpoint cp{std::move(file.meta), {std::move(file.cloud), {}, {}, {}}, std::move(file.extra)};
  size_t k = 0;
  for (Attr a : splat::kCloudAttrs) {
    cp.state.m[a] = std::move(file.trainer[k++]);
    cp.state.v[a] = std::move(file.trainer[k++]);
  }
  for (std::vector<float>& s : cp.state.stats) s = std::move(file.trainer[k++]);
  return cp;
}

}  // namespace

void write_checkpoint(const std::filesystem::path& path, const Checkpoint& checkpoint) {
  run::write_checkpoint(path, file_of(checkpoint));
}

void write_checkpoint_rotating(const std::filesystem::path& path, const std::filesystem::path& previous,
                               const Checkpoint& checkpoint, bool rotate) {
  run::write_checkpoint_rotating(path, previous, file_of(checkpoint), rotate);
}

Checkpoint read_checkpoint(const std::filesystem::path& path) { return from_file(run::read_checkpoint(path)); }

LoadedCheckpoint read_checkpoint_or_previous(const std::filesystem::path& path, const std::filesystem::path& previous) {
  run::LoadedCheckpoint loaded = run::read_checkpoint_or_previous(path, previous);
  return {from_file(std::move(loaded.checkpoint)), std::move(loaded.path), std::move(loaded.newest_problem)};
}

}  // namespace s4d::model
