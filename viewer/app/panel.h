// The ImGui panel: device, Gaussian count and frame times; the time slider with play/pause,
// speed and looping; the style list with a second style to blend in and the blend factor; the
// dataset cameras; screenshot and camera-path buttons.
#pragma once
#include <string>
#include <vector>

#include "s4d/viewer/playback.h"
#include "style_switch.h"

namespace s4d::viewer {

struct PanelInfo {
  std::string device;
  uint32_t gaussians = 0;
  uint32_t width = 0, height = 0;
  double frame_ms = 0;   // wall time of the last frame loop iteration
  double render_ms = 0;  // rasterize + pack of the last frame (near 0 when it reused the last pixels)
  uint32_t render_width = 0, render_height = 0;  // the last rasterized image (smaller while moving)
  bool dynamic = false;  // the scene moves with time
  const std::vector<std::string>* cameras = nullptr;
  const std::vector<std::string>* styles = nullptr;
  bool recording = false;
  size_t recorded = 0;   // camera-path frames so far
  std::string message;   // the last saved file or a note
};

struct PanelActions {
  int snap_camera = -1;
  bool screenshot = false, toggle_record = false;
};

// Draws the panel between ImGui's new frame and its render; edits `playback` and `styles` in place.
PanelActions draw_panel(const PanelInfo& info, Playback& playback, StyleSelection& styles);

}  // namespace s4d::viewer
