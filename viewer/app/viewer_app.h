// The windowed viewer: a GLFW window with a Vulkan swapchain. Each frame: FrameRenderer
// rasterizes and packs on the device, one command buffer copies the pixels into the acquired
// swapchain image and draws the ImGui panel over them, and the image is presented; no pixel is read
// back to the host unless a screenshot is asked for. While the view changes (camera, time, style,
// blend, window size) frames are rasterized at AdaptiveResolution's scale and upsampled; once the
// view has been still for the policy's settle time a frame refines to full resolution, and later
// still frames reuse its pixels without rasterizing. Screenshots are always of a full-resolution frame. Resizes recreate the swapchain; while the
// window is minimised nothing renders and playback stops advancing.
#pragma once
#include <cstdint>
#include <filesystem>
#include <string>

#include "s4d/scene/trained_run.h"

namespace s4d::viewer {

struct ViewerOptions {
  scene::StyleChoice style;  // a style of the run, or the blend of two
  splat::Storage storage = splat::Storage::f32;  // f16: SH and style MLPs as halves (scene::open_scene)
  size_t camera = 0;  // dataset camera to start from
  double time = 0;    // in [0, 1]
  bool play = false;  // start playing
  uint32_t exit_after = 0;  // quit after this many presented frames (tests); 0: when closed
  std::filesystem::path out_dir;  // screenshots and camera paths go here
  std::filesystem::path record;   // record the camera path from the first frame, written on exit
  int width = 0, height = 0;      // window size; 0: the first camera's aspect, 640..1280 px wide
  double frame_budget_ms = 100;   // frame time aimed for while the view changes; 0: always full resolution
};

struct ViewerSummary {
  uint64_t frames = 0;
  double mean_frame_ms = 0;
  uint64_t rasterized = 0;      // frames rasterized (the others reused the last full-resolution pixels)
  double mean_scale = 0;        // mean render scale of the rasterized frames
  double mean_rasterized_ms = 0;  // mean time of a rasterized frame, from the render to its pixels on screen
  // Views rasterized again because the rasterizer's instance buffers were too small for them (not
  // in `rasterized`): the first frame of a session, and rarely a later one that needs more.
  uint64_t rerendered = 0;
  std::string device;
};

// Opens the run's scene source on the window's device; switching styles in the panel reopens it,
// moving the blend factor re-blends it (style_switch.h).
ViewerSummary run_viewer(const scene::TrainedRun& run, const ViewerOptions& options);

}  // namespace s4d::viewer
