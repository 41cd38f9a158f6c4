// Settings of a training run and the presets that choose them (ALGORITHMS.md 2; graphdeco's
// defaults scaled to the iteration count). Everything a run needs to be resumed is here, so it is
// stored in the run directory and read back by --resume.
#pragma once
#include <array>
#include <cstdint>
#include <string>

#include <nlohmann/json_fwd.hpp>

namespace s4d::train {

struct TrainConfig {
  std::string preset = "default";
  uint32_t iterations = 30000;
  uint32_t seed = 0;
  // Data.
  int downscale = 1;
  double max_time = 1.0;  // train and test on views with time <= max_time (0: the first frame only)
  std::array<float, 3> background{0, 0, 0};
  // Model.
  int sh_degree = 3;              // stored degree; the active degree grows by one every sh_up_every
  uint32_t sh_up_every = 1000;
  uint32_t random_init_points = 2000;  // when the dataset has no point cloud
  // Loss: (1 - ssim_weight) L1 + ssim_weight (1 - SSIM).
  float ssim_weight = 0.2f;
  // Learning rates (ALGORITHMS.md 2.1); means are scaled by the scene extent and decay to
  // means_lr_final over the run.
  double means_lr = 1.6e-4, means_lr_final = 1.6e-6, sh_dc_lr = 0.0025, sh_rest_lr = 0.000125, opacity_lr = 0.05,
         scaling_lr = 0.005, rotation_lr = 0.001;
  double lr_scale = 1.0;  // multiplies every learning rate (halved again on each non-finite rollback)
  // Densification (ALGORITHMS.md 2.2).
  uint32_t densify_from = 500, densify_until = 15000, densify_every = 100, opacity_reset_every = 3000;
  float grad_threshold = 0.0002f, percent_dense = 0.01f, min_opacity = 0.005f;
  float max_screen_radius = 20.0f;  // pixels; applies after the first opacity reset
  uint32_t budget = 1000000;        // at most this many Gaussians
  // Runs.
  uint32_t test_every = 1000;
  uint32_t checkpoint_every = 1000;
};

// "fast", "default" or "quality"; std::invalid_argument naming the preset otherwise.
TrainConfig preset_config(const std::string& name);
// Sets the run length and rescales every schedule of the preset (densification window, opacity
// resets, SH growth, tests, checkpoints) by the same factor, so --iters keeps the preset's shape.
void set_iterations(TrainConfig& config, uint32_t iterations);

nlohmann::json to_json(const TrainConfig& config);
// Missing keys keep their defaults; a key of the wrong type is an error naming it.
TrainConfig config_from_json(const nlohmann::json& j);

}  // namespace s4d::train
