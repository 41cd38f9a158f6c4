// Stage 4 of Style4D, "Style Gaussians" (ALGORITHMS.md 4.3): the run's geometry stays frozen; each
// Gaussian's colour and opacity change and (method "full") its tiny MLP on (time, ray-hit depth)
// are trained against the stylized frames of stage 3 with L1 + image TV. Progress, checkpoints
// (RUN/style/NAME/checkpoint.s4dckpt, atomic), interruption, resume and rollback on a non-finite
// loss as in training (one loop runs both: train/stage_runner.h).
#pragma once
#include <atomic>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "s4d/data/dataset.h"
#include "s4d/engine/context.h"
#include "s4d/scene/trained_run.h"
#include "s4d/style_gaussians/style_config.h"
#include "s4d/train/evaluate.h"

namespace s4d::style_gaussians {

struct StyleResult {
  bool complete = false;  // false: interrupted; the checkpoint holds the state to resume from
  uint32_t iteration = 0;
  double seconds = 0;     // training time, summed over a stopped style's runs
  uint32_t stylized_gaussians = 0;  // inside the region (all without one)
  train::Evaluation test; // renders of the test views against their stylized frames (complete runs)
  nlohmann::json time_budget;  // with a deadline: the plans (style_budget.h); else null
};

class StyleTrainer {
 public:
  // Trains style `name` of `run` against `stylized` (stylized_frames.h) with `config` (method full or
  // colors). Continues from RUN/style/NAME/checkpoint.s4dckpt when there is one written with the same
  // settings; throws std::runtime_error when its settings differ (name the difference) or the run's
  // Gaussians changed since. `deadline` > 0: the stage's training seconds (summed over a stopped style's runs) to end
  // by; its length is re-planned as it runs (style_budget.h), from `config`'s lengths.
  StyleTrainer(engine::Context& ctx, const scene::TrainedRun& run, const data::Dataset& stylized, std::string name,
               const StyleConfig& config, double deadline = 0);
  ~StyleTrainer();

  // Trains to config.iterations or until `stop`; on completion writes RUN/style/NAME/style.s4dstyle
  // and RUN/style/NAME/eval/*.png. Progress goes to stderr.
  StyleResult run(const std::atomic<bool>& stop);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace s4d::style_gaussians
