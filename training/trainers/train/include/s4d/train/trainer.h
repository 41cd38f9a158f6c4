// Training stages 1 and 2 (ARCHITECTURE.md): static Gaussians (3DGS on every selected frame as if
// the scene did not move; ALGORITHMS.md 2), then the 4DGS fine stage (canonical Gaussians and a
// HexPlane deformation field trained together, a batch of views per step; ALGORITHMS.md 3).
// Densification and opacity resets on the GPU; checkpoints, resume, interruption and non-finite
// recovery in both stages.
#pragma once
#include <atomic>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "s4d/data/dataset.h"
#include "s4d/engine/context.h"
#include "s4d/run/names.h"
#include "s4d/run/run_dir.h"
#include "s4d/run/run_json.h"
#include "s4d/run/train_config.h"
#include "s4d/train/evaluate.h"

namespace s4d::train {

struct TrainResult {
  bool complete = false;  // false: interrupted; the checkpoint holds the state to resume from
  run::Stage stage = run::Stage::coarse;  // where the run stopped
  uint32_t iteration = 0; // within that stage
  uint32_t num_gaussians = 0;
  double seconds = 0;  // training time over all sessions of the run
  uint32_t rollbacks = 0;
  Evaluation test;  // the last evaluation (all test views when complete); train.json also keeps the static stage's
  // Non-empty when the finished model is degenerate: (nearly) no Gaussians, or test renders no
  // better than the background alone. Names the cause and the step where the model collapsed.
  std::string degenerate;
};

// Fewer Gaussians than this at the end is no model.
inline constexpr uint32_t kDegenerateGaussians = 16;
// Test renders within this of an empty render's PSNR show nothing of the scene.
inline constexpr double kDegenerateMarginDb = 1.0;

// Whether the run in `run_dir` has finished: its train.json says complete. A finished run's results
// are the only copy of its final model, so it is never trained again (Trainer::resume refuses it).
bool run_finished(const std::filesystem::path& run_dir);

class Trainer {
 public:
  // A new run into `run_dir`, which must not exist or be empty (a run is never overwritten).
  // Writes RUN/run.json at once. `loaded`: the dataset as load_options(config, false) loads it from
  // data_dir, when the caller has it already (style4d train checks it first), so it is not read twice.
  Trainer(engine::Context& ctx, const std::filesystem::path& data_dir, const run::TrainConfig& config,
          const std::filesystem::path& run_dir, std::optional<data::Dataset> loaded = std::nullopt);
  // Continues the run in `run_dir` from its checkpoint (or from the previous one when that is damaged);
  // refuses when neither loads and the run has results, restarts a run killed before its first checkpoint.
  // Refuses a finished run (run_finished), whatever state its checkpoints are in.
  static std::unique_ptr<Trainer> resume(engine::Context& ctx, const std::filesystem::path& run_dir);
  ~Trainer();

  // Trains both stages to their configured iteration counts, or until `stop` becomes true (then
  // writes a checkpoint and returns with complete = false). Progress goes to stderr.
  TrainResult run(const std::atomic<bool>& stop);

  const run::TrainConfig& config() const { return config_; }
  const data::Dataset& dataset() const { return dataset_; }

 private:
  struct Impl;
  Trainer(engine::Context& ctx, const run::RunDir& run, const run::RunJson& run_json);

  run::TrainConfig config_;
  data::Dataset dataset_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace s4d::train
