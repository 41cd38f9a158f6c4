// Headless capture: one frame of a run from one of its dataset cameras, through FrameRenderer
// (the window's code path) but without a window, written as a PNG. Needs no display.
#pragma once
#include <filesystem>
#include <string>

#include "s4d/engine/context.h"
#include "s4d/viewer/run_scene.h"

namespace s4d::viewer {

struct CaptureRequest {
  std::filesystem::path png;
  double time = 0;      // in [0, 1]
  size_t camera = 0;    // index into RunScene::cameras
  std::string style = "original";
};

// Throws std::invalid_argument for a camera index or time out of range or an unknown style.
void capture(engine::Context& ctx, const RunScene& scene, const CaptureRequest& request);

}  // namespace s4d::viewer
