// Stage 1, static Gaussians (ALGORITHMS.md 2; the coarse stage of 4DGS): 3DGS trained on every
// selected frame as if the scene did not move. One random training view per iteration; densification
// and opacity resets on the GPU; checkpoints, resume, interruption and non-finite recovery.
#pragma once
#include <atomic>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "s4d/data/dataset.h"
#include "s4d/engine/context.h"
#include "s4d/train/evaluate.h"
#include "s4d/train/run_dir.h"
#include "s4d/train/train_config.h"

namespace s4d::train {

struct TrainResult {
  bool complete = false;  // false: interrupted; the checkpoint holds the state to resume from
  uint32_t iteration = 0;
  uint32_t num_gaussians = 0;
  double seconds = 0;  // training time over all sessions of the run
  uint32_t rollbacks = 0;
  Evaluation test;  // the last evaluation (all test views when complete)
};

class StaticTrainer {
 public:
  // A new run into `run_dir`, which must not exist or be empty (a run is never overwritten).
  // Writes RUN/run.json at once.
  StaticTrainer(engine::Context& ctx, const std::filesystem::path& data_dir, const TrainConfig& config,
                const std::filesystem::path& run_dir);
  // Continues the run in `run_dir` from its checkpoint (or from the start when it has none yet).
  static std::unique_ptr<StaticTrainer> resume(engine::Context& ctx, const std::filesystem::path& run_dir);
  ~StaticTrainer();

  // Trains until the configured iteration count, or until `stop` becomes true (then writes a
  // checkpoint and returns with complete = false). Progress goes to stderr.
  TrainResult run(const std::atomic<bool>& stop);

  const TrainConfig& config() const { return config_; }
  const data::Dataset& dataset() const { return dataset_; }

 private:
  struct Impl;
  StaticTrainer(engine::Context& ctx, const RunDir& run, const nlohmann::json& run_json);

  TrainConfig config_;
  data::Dataset dataset_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace s4d::train
