// The time a run will take, told up front: from the measured seconds of its first static steps,
// extrapolated over both stages with the stage-scaling measurements (docs/benchmarks.md, "Stage
// scaling": a static step's cost grows as Gaussians^0.5, a 4DGS step's as Gaussians^0.65, and a
// 4DGS step costs about 2.5 static steps per view on lavapipe). A CPU user learns in seconds that
// full-resolution Neu3D takes days; the stages' own ETAs refine it as they run.
#pragma once
#include <cstdint>
#include <string>

#include "s4d/run/train_config.h"

namespace s4d::train {

// A range per stage: the low end keeps the probe's step time throughout (no growth, a 4DGS step per
// view costing one static step), the high end lets the Gaussians fill the budget. On a D-NeRF-like
// object that kept 885 of 15,000 Gaussians the run took 447 s against a 1.1-4.0 h high end: the
// low end is the one to read for clouds that stay small.
struct TimeEstimate {
  double static_seconds = 0, fine_seconds = 0;          // high end
  double static_seconds_low = 0, fine_seconds_low = 0;  // low end
  double probe_seconds_per_step = 0;  // measured
  uint32_t probe_gaussians = 0;       // Gaussians during the probe
};

// Assumes densification fills the budget linearly over its window (the built-in scene fills it by
// the window's end); a scene that grows less trains faster than estimated.
TimeEstimate estimate_time(const run::TrainConfig& config, double seconds_per_static_step, uint32_t gaussians);

// One line: "estimate: static stage 3-5 min, 4DGS stage 5-17 min (from 30 steps at 0.210 s with 4000 Gaussians; ...)".
std::string describe(const TimeEstimate& estimate, uint32_t probe_steps);

}  // namespace s4d::train
