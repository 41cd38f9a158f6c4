// Headless capture: one frame of a run from one of its dataset cameras, through FrameRenderer
// (the window's code path) but without a window, written as a PNG. Needs no display.
#pragma once
#include <filesystem>

#include "s4d/engine/context.h"
#include "s4d/scene/trained_run.h"

namespace s4d::viewer {

struct CaptureRequest {
  std::filesystem::path png;
  double time = 0;      // in [0, 1]
  size_t camera = 0;    // index into dataset_cameras(run.dataset)
  scene::StyleChoice style;  // a style of the run, or the blend of two
  splat::Storage storage = splat::Storage::f32;  // f16: SH and style MLPs as halves (scene::open_scene)
};

// Throws std::invalid_argument for a camera index or time out of range; scene::open_scene's errors
// (an unknown style, styles that cannot be blended, a run's unreadable files) propagate.
void capture(engine::Context& ctx, const scene::TrainedRun& run, const CaptureRequest& request);

}  // namespace s4d::viewer
