// train-stylizer's checkpoint, OUT/checkpoint.safetensors beside the weights it continues: Adam's
// moments of every trained tensor ("<file>.<tensor>.exp_avg" and ".exp_avg_sq", PyTorch's names,
// flat), the CCPL projection heads (no weights file holds them: "ccpl_heads.<level>.<0|2>.weight",
// ".bias", as CCPL's Sequential), and in its metadata the steps done, the --losses set and the
// settings a continued run must keep (--batch, --crop, --resize, --lr, --seed). The
// weights files carry the same step in their metadata, so a folder whose weights and checkpoint
// disagree is refused, not mixed.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "s4d/engine/buffer.h"
#include "s4d/engine/context.h"
#include "s4d/optim/adam_tensor.h"

namespace s4d::stylizer_train {

struct CheckpointState {
  int step = 0;        // Adam steps done
  std::string losses;  // the --losses set trained
  // The options a continued run must repeat, by name ("batch", "crop", "resize", "lr", "seed"),
  // as their text (lr with the fewest of 15 or 17 digits that reads back exactly).
  std::vector<std::pair<std::string, std::string>> settings;
};

// A tensor the checkpoint holds itself, flat.
struct CheckpointTensor {
  std::string name;
  engine::Buffer* buffer;
};

// Writes path atomically (a temporary file renamed).
void write_checkpoint(engine::Context& ctx, const std::filesystem::path& path, const CheckpointState& state,
                      const std::vector<optim::AdamTensor>& moments, const std::vector<CheckpointTensor>& tensors);

// The metadata. Throws std::runtime_error naming the file and the missing or bad field; `keys` are
// the settings' names expected.
CheckpointState read_checkpoint_state(const std::filesystem::path& path, const std::vector<std::string>& keys);

// Uploads the moments of every tensor (named "decoder.1.weight", "mcc_module.MCCN.fc.bias", ...);
// throws std::runtime_error naming the file and tensor that is missing or of another size.
void read_checkpoint_moments(const std::filesystem::path& path, std::vector<optim::AdamTensor>& moments);
// Uploads the tensors; throws as read_checkpoint_moments.
void read_checkpoint_tensors(engine::Context& ctx, const std::filesystem::path& path,
                             const std::vector<CheckpointTensor>& tensors);

// The "step" in a weights file's metadata; -1 where it has none (a folder not written by
// train-stylizer, or --init's).
int weights_step(const std::filesystem::path& path);

}  // namespace s4d::stylizer_train
