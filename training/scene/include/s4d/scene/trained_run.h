// Opens a training run directory for rendering: its dataset (cameras, times, test views, loaded with
// the run's own downscale and background) and the scene source of the requested style.
//
// A run today is the static stage: RUN/run.json (data = dataset path, settings), RUN/geometry/
// gaussians.ply. When the deformation field and styles are written into runs, this is where their
// sources are chosen.
#pragma once
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include "s4d/data/dataset.h"
#include "s4d/engine/context.h"
#include "s4d/scene/scene_source.h"

namespace s4d::scene {

struct TrainedRun {
  std::filesystem::path root;
  std::string stage;  // run.json "stage", e.g. "static"
  data::Dataset dataset;
  std::unique_ptr<SceneSource> scene;
};

// `style`: nullopt renders the original scene. Throws std::runtime_error naming the file and field:
// RUN or RUN/run.json missing, run.json unreadable or without 'data' / 'settings', the dataset it
// names missing or unloadable, RUN/geometry/gaussians.ply missing or unreadable; and
// "no style NAME in RUN (styles are trained with style4d stylize, not built yet)" for any style.
TrainedRun open_trained_run(engine::Context& ctx, const std::filesystem::path& run,
                            const std::optional<std::string>& style = std::nullopt);

}  // namespace s4d::scene
