// Settings chosen from the data rather than from the preset alone: a recipe tuned on a synchronized
// multi-view capture breaks on a monocular one (and the other way round), so the presets leave some
// settings to the data, and what was chosen, and why, goes into train.json ("recipe").
#pragma once
#include <nlohmann/json.hpp>

#include "s4d/data/dataset.h"
#include "s4d/run/train_config.h"

namespace s4d::train {

// How a run loads its dataset: downscale and frames from the settings; a new run takes the dataset's
// background unless one was asked for, a resumed run keeps its own.
data::LoadOptions load_options(const run::TrainConfig& config, bool resumed);

// Training views per distinct time: 1 for a monocular capture (D-NeRF, HyperNeRF: one camera per
// moment), the camera count for a synchronized rig (DyNeRF).
double train_views_per_time(const data::Dataset& dataset);

// "monocular" (at most 1.5 training views per time) or "multi-view".
std::string capture_kind(const data::Dataset& dataset);

// Resolves the settings a preset leaves to the data (today: static_max_time < 0, "auto") and
// returns the choices with their reasons, e.g. {"capture": "monocular", "views_per_time": 1,
// "static_max_time": {"value": 1, "why": "..."}}. Explicit settings are kept and named as such.
nlohmann::json adapt_to_data(run::TrainConfig& config, const data::Dataset& dataset);

}  // namespace s4d::train
