// `stylize --time-budget`: stage 4's length fitted to the seconds it is given, keeping the setting's
// shape (the share of steps that train the MLPs). A colour-only step and an MLP step cost different
// amounts (the MLP one about 3.4x on lavapipe, built-in scene, 2026-11-28), so the plan keeps one
// measured cost per phase: before the MLPs join, both phases are scaled by one factor from the
// measured colour step and kMlpStepRatio; once they join, their own measured step fits the rest.
#pragma once
#include <cstdint>

#include "s4d/style_gaussians/style_config.h"

namespace s4d::style_gaussians {

// What an MLP step costs in colour-only steps until one is measured: 3.4 measured on lavapipe
// (the built-in scene's fast run, 15,000 Gaussians, 0.089 s against 0.30 s), rounded up, because
// finishing early costs less than running over.
inline constexpr double kMlpStepRatio = 3.5;

struct StyleLengths {
  uint32_t iterations = 0, mlp_iterations = 0;
};

// The lengths whose steps left end at `deadline`: `now` is the stage's seconds after `done` steps of
// `current` (the lengths planned so far), each further step takes `seconds_per_step` (a step of the
// phase running now) and, before the MLPs join, an MLP step `mlp_ratio` times that. `start` holds
// the setting's own lengths; every phase stays within train::kMaxStretch x its starting length, and
// the phase running now ends no earlier than `done`.
StyleLengths fitted_style_lengths(const StyleConfig& start, const StyleConfig& current, uint32_t done, double deadline,
                                  double now, double seconds_per_step, double mlp_ratio);

// Whether step `done` + 1 trains the MLPs under `c` (method full only).
bool mlp_phase(const StyleConfig& c, uint32_t done);

}  // namespace s4d::style_gaussians
