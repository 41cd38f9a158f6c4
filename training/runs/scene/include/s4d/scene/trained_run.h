// Opens a training run directory for rendering (the render protocols, the viewer, export-ply):
// read_trained_run reads what the run is on the host (its settings, stage and dataset, loaded with
// the run's own downscale and background) and checks that every file its stage needs is there;
// open_scene then gives the scene source of one style, or of the blend of two, on a device.
//
// What a run needs, by run.json "stage": "static": RUN/geometry/gaussians.ply; "4dgs":
// RUN/checkpoint/state.s4dckpt (canonical Gaussians and the deformation field, trained_field.h).
// Both render at the SH degree the trainer evaluated the finished run at.
#pragma once
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "s4d/data/dataset.h"
#include "s4d/engine/context.h"
#include "s4d/run/names.h"
#include "s4d/run/train_config.h"
#include "s4d/scene/blended_scene.h"
#include "s4d/scene/scene_source.h"

namespace s4d::scene {

struct TrainedRun {
  std::filesystem::path root;
  run::Stage stage = run::Stage::coarse;  // run.json "stage": its last stage (static: coarse, 4dgs: fine)
  run::TrainConfig config;
  data::Dataset dataset;
  std::vector<std::string> styles{"original"};  // what open_scene takes; "original" is the unstylised scene
};

// Throws std::runtime_error naming the file and field: RUN not a directory; RUN/run.json unreadable,
// without 'data' or 'settings', or with a stage this build does not render; and, all at once as "an
// incomplete run" with how to finish it, every missing file: run.json, the stage's files above, the
// dataset run.json names. Dataset loading errors propagate.
TrainedRun read_trained_run(const std::filesystem::path& run);

// The scene source of `style` (one of run.styles). Throws std::runtime_error naming the file and what
// is wrong with it (trained_field.h for 4DGS runs; an empty or unreadable PLY), and "no style NAME in
// RUN; it has: ..." for a style the run does not have. `storage` f16 holds the SH and the style MLPs
// on the device as packed halves (render only: StaticScene, DeformedScene and StyledScene say which),
// and refuses a value beyond half's range (splat::upload_as).
std::unique_ptr<SceneSource> open_scene(engine::Context& ctx, const TrainedRun& run,
                                        const std::string& style = "original",
                                        splat::Storage storage = splat::Storage::f32);

// The blend of styles `a` and `b` of the run (either may be "original") with weight `alpha` in [0, 1]
// on b (style_blend.h). Throws open_scene's errors for a style the run does not have, and
// std::invalid_argument naming both styles for a "scratch" style (its own geometry) and what
// blend_styles refuses.
std::unique_ptr<BlendedScene> open_blend(engine::Context& ctx, const TrainedRun& run, const std::string& a,
                                         const std::string& b, float alpha,
                                         splat::Storage storage = splat::Storage::f32);

// What a render or the viewer shows: `style` alone when `mix` is empty, else open_blend(style, mix, alpha).
struct StyleChoice {
  std::string style = "original";
  std::string mix;
  float alpha = 0;
};
std::unique_ptr<SceneSource> open_scene(engine::Context& ctx, const TrainedRun& run, const StyleChoice& choice,
                                        splat::Storage storage = splat::Storage::f32);

}  // namespace s4d::scene
