// RUN/run.json: what a run was trained from and how, written once when the run starts (the trainer)
// and read by --resume and by everything that renders the run.
#pragma once
#include <filesystem>
#include <optional>

#include <nlohmann/json.hpp>

#include "s4d/run/names.h"
#include "s4d/run/run_dir.h"
#include "s4d/run/train_config.h"

namespace s4d::run {

struct RunJson {
  std::filesystem::path data;  // "data": the dataset, absolute
  // "stage": what the run's geometry is, by its last stage ("static", "4dgs"); absent in runs written
  // before stages were named.
  std::optional<Stage> stage;
  nlohmann::json dataset;  // "dataset": facts about the data and the choices made from it; null when absent
  TrainConfig settings;    // "settings", validated
};

// Atomic; "data" is stored absolute.
void write_run_json(const RunDir& run, const RunJson& run_json);

// Throws std::runtime_error naming the file and the field: unreadable or not JSON, not an object,
// 'data' missing or not a string, 'settings' missing or refused (config_from_json), 'stage' not
// "static" or "4dgs". Whether the file exists is the caller's to say (a missing run.json means
// different things to --resume and to a render).
RunJson read_run_json(const RunDir& run);

}  // namespace s4d::run
