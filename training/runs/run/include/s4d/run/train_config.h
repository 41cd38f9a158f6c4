// Settings of a training run and the presets that choose them (ALGORITHMS.md 2; graphdeco's
// defaults scaled to the iteration count). Everything a run needs to be resumed is here, so it is
// stored in the run directory and read back by --resume.
#pragma once
#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "s4d/deform/field_config.h"
#include "s4d/run/names.h"

namespace s4d::run {

struct TrainConfig {
  std::string preset = "default";
  uint32_t iterations = 30000;
  uint32_t seed = 0;
  // Data.
  int downscale = 1;
  double max_time = 1.0;  // train and test on views with time <= max_time (0: the first frame only)
  // Only these frames of the capture, "N" or "A:B" (data::parse_frame_range), their times mapped back
  // onto [0, 1]; empty: every frame.
  std::string frames;
  // The static stage trains on the views with time <= static_max_time, the fine stage on all: 0 makes
  // the first frame the canonical scene (large motions survive; see docs/training.md). Negative:
  // chosen from the data when training starts (adapt_to_data: 0 multi-view, 1 monocular); a run's
  // run.json always holds the chosen value.
  double static_max_time = 1.0;
  std::array<float, 3> background{0, 0, 0};
  // Whether `background` was asked for (--background, --set background=...); otherwise a new run takes
  // the dataset's (found from its frames) and stores it here. Not stored: a run's background is settled.
  bool background_given = false;
  // Whether the fine stage's length was asked for (--fine-iters, --set fine_iterations=...);
  // otherwise a new run whose frames show no motion skips it (train/scene_motion.h). Not stored.
  bool fine_iterations_given = false;
  // Model.
  int sh_degree = 3;              // stored degree; the active degree grows by one every sh_up_every
  uint32_t sh_up_every = 1000;
  // true: sh_degree is the most the run may keep. Once the top degree has trained for sh_up_every
  // steps, the run measures what each degree adds on held-out views and keeps the lowest that
  // serves them as well (train/sh_choice.h); the choice then replaces sh_degree and this turns false.
  // false for runs from before it existed; the presets set it, and --sh-degree D turns it off.
  bool sh_degree_auto = false;
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
  // Whether the budget was asked for (--budget, --set budget=...); otherwise a time budget may cut
  // it (train/time_budget.h, gaussian_budget_share). Not stored.
  bool budget_given = false;
  // The Gaussian budget grown while held-out error still falls (train/budget_growth.h): a new run
  // densifies to this share of `budget` first and doubles it while a paired probe shows the held-out
  // views gain. 0: `budget` from the start (runs from before it existed); the presets set 0.25.
  double budget_start = 0;
  // Growth into missed content (train/missing_content.h): at every densification, this many
  // training views are rendered and Gaussians are seeded where the render misses the ground truth.
  // 0: off (runs from before it existed); the presets set 4.
  uint32_t seed_views = 0;
  // Stage 2, the 4DGS fine stage (ALGORITHMS.md 3; DyNeRF settings). 0 iterations: static only.
  // Its iteration counter, learning-rate schedules and densification window restart at 1; every
  // log-linear schedule spans its stage (4DGaussians spans 20000 steps in both stages).
  uint32_t fine_iterations = 14000;
  uint32_t fine_batch = 4;           // views per step; their gradients are summed
  float fine_ssim_weight = 0.0f;     // 4DGaussians trains the fine stage on L1 only
  uint32_t fine_densify_until = 10000;
  // Time curriculum: the fine stage's views open from time 0 to 1 over this fraction of the stage
  // (0: every time from the start, as 4DGaussians).
  double fine_time_ramp = 0.0;
  // While the window opens, every other view comes from its newest fine_time_front of time, so a
  // newly opened frame is trained before the next opens (uniform sampling gives the last frames
  // under one view each). 0: uniform over the window.
  double fine_time_front = 0.0;
  std::array<uint32_t, 4> field_resolution{64, 64, 64, 150};  // x, y, z, t; t is not multiplied
  // The times at the time axis's first and last texel (deform::FieldConfig::time_range). {-1, 1}:
  // 4DGaussians' mapping, where times in [0, 1] reach the upper half of each time plane; the presets
  // keep it: {0, 1} (the times every loader gives) scored 0.7 to 1.4 dB lower (docs/trade.md).
  std::array<float, 2> field_time{-1, 1};
  std::vector<uint32_t> field_multires{1, 2};
  uint32_t field_channels = 16, field_width = 128, field_trunk_extra = 0;
  uint32_t field_heads = 31;  // S4D_DEFORM_HEAD_* bits: dx ds dr do dsh (7: dx ds dr)
  double deform_lr = 1.6e-4, deform_lr_final = 1.6e-5, grid_lr = 1.6e-3, grid_lr_final = 1.6e-4;  // x extent
  float plane_tv_weight = 2e-4f, time_smoothness_weight = 1e-3f, l1_time_planes_weight = 1e-4f;
  // Deform only what moves: once densification has ended (and every motion_every iterations after),
  // Gaussians whose mean moves less than static_motion x extent over motion_samples times in [0, 1]
  // skip the field (offsets 0, no field gradient): the motion split's still Gaussians. 0: off. (The
  // name static_motion is run.json's key and --static-motion's.)
  float static_motion = 0.0f;
  uint32_t motion_samples = 8, motion_every = 500;
  // The field fitted to what moves (train/field_box.h): after this fraction
  // of the fine stage that follows the opening of its time window (fine_time_ramp), the planes are
  // resampled from the initial cloud's bounds onto the bounds of the Gaussians that move, at the
  // same texel size, so fewer texels cover the motion, and onto as few time texels as their paths
  // need. 0: off (runs from before it existed); the presets set 0.2.
  double field_fit = 0;
  // Runs.
  uint32_t test_every = 1000;
  uint32_t checkpoint_every = 1000;
  // Seconds of training (both stages, every session) the run is fitted to: the stages' lengths and
  // schedules are planned from measured step times (train/time_budget.h) and run.json holds the
  // latest plan. 0: the lengths as set.
  double time_budget = 0;
};

// "fast", "default" or "quality"; std::invalid_argument naming the preset otherwise.
TrainConfig preset_config(const std::string& name);
// Sets the run length and rescales every schedule of the preset (densification window, opacity
// resets, SH growth, tests, checkpoints) by the same factor, so --iters keeps the preset's shape.
void set_iterations(TrainConfig& config, uint32_t iterations);
// The same for the fine stage (its densification window).
void set_fine_iterations(TrainConfig& config, uint32_t iterations);

// The stage a run with these settings ends in: fine when it has fine iterations.
Stage last_stage(const TrainConfig& config);

// The SH degree the renderer uses after `iterations_done` iterations of both stages together: one
// more every sh_up_every, at most sh_degree (the degree is not reset by the fine stage).
int active_sh_degree(const TrainConfig& config, uint32_t iterations_done);

// The deformation field of the 4DGS stage, over the AABB of the initial points (a run's checkpoint
// stores it as meta aabb_min / aabb_max).
deform::FieldConfig field_config(const TrainConfig& config, const std::array<float, 3>& aabb_min,
                                 const std::array<float, 3>& aabb_max);

// The one check of settings, wherever they come from (command line, --set, RUN/run.json, presets):
// throws std::runtime_error "SOURCE: field 'KEY' = VALUE: why" for the first setting outside its
// range (ranges per key in train_config_check.cpp; the deformation field's are the kernels' limits,
// s4d_deform.h). SOURCE says where the settings came from: a file (RUN/run.json), "--set",
// "command line", "preset fast". `flags` maps a setting to the command-line option that set it: a
// setting refused there is named as the user wrote it, "--downscale 0: must be at least 1".
void validate(const TrainConfig& config, const std::string& source, const std::map<std::string, std::string>& flags = {});

// The message format of settings errors: "SOURCE: field 'KEY' = VALUE: why".
std::string setting_error(const std::string& source, const std::string& key, const std::string& value,
                          const std::string& why);

nlohmann::json to_json(const TrainConfig& config);
// Missing keys keep their defaults. Not an object, a key of the wrong type (a string for a number,
// 2.5 or -1 for a count) or a value validate() refuses is a std::runtime_error in validate's format,
// naming `source` (the file the settings came from).
TrainConfig config_from_json(const nlohmann::json& j, const std::string& source = "training settings");

}  // namespace s4d::run
