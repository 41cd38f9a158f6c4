// The windowed viewer: a GLFW window with a Vulkan swapchain. Each frame: FrameRenderer
// rasterizes and packs on the device, one command buffer copies the pixels into the acquired
// swapchain image and draws the ImGui panel over them, and the image is presented; no pixel is read
// back to the host unless a screenshot is asked for. Resizes recreate the swapchain; while the
// window is minimised nothing renders and playback stops advancing.
#pragma once
#include <cstdint>
#include <filesystem>
#include <string>

#include "s4d/scene/trained_run.h"

namespace s4d::viewer {

struct ViewerOptions {
  scene::StyleChoice style;  // a style of the run, or the blend of two
  size_t camera = 0;  // dataset camera to start from
  double time = 0;    // in [0, 1]
  bool play = false;  // start playing
  uint32_t exit_after = 0;  // quit after this many presented frames (tests); 0: when closed
  std::filesystem::path out_dir;  // screenshots and camera paths go here
  std::filesystem::path record;   // record the camera path from the first frame, written on exit
  int width = 0, height = 0;      // window size; 0: the first camera's aspect, 640..1280 px wide
};

struct ViewerSummary {
  uint64_t frames = 0;
  double mean_frame_ms = 0;
  std::string device;
};

// Opens the run's scene source on the window's device; switching styles in the panel reopens it,
// moving the blend factor re-blends it (style_switch.h).
ViewerSummary run_viewer(const scene::TrainedRun& run, const ViewerOptions& options);

}  // namespace s4d::viewer
