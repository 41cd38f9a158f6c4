// Where a training step's time goes: the stages the trainer and the rasterizer mark with
// engine::StageScope, and the "stage_ms" object train.json and the s4d_bench_* programs write from
// an engine::StageTimer's totals.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "s4d/engine/stage_timer.h"

namespace s4d::run {

// In the order of a step; StageScope names outside this list still get their own entry.
inline const std::vector<std::string> kStepStages = {"project", "sort",  "raster", "loss",
                                                     "backward", "field", "adam",   "densify"};

// {"clock", "note", "iterations", "step_ms", "step_ms_per_iteration", "stages_sum_ms",
//  "stages": {name: {"ms", "ms_per_iteration"}, ..., "other": {...}}}: totals over `iterations`
// iterations (0: no per-iteration figures).
nlohmann::json stage_ms_json(const engine::StageTotals& totals, uint64_t iterations);

}  // namespace s4d::run
