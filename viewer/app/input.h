// Mouse and keyboard, polled once per frame. Left drag orbits, right or middle drag pans, the
// wheel zooms; W/A/S/D fly forward/left/back/right, Q/E down/up (Shift: 4x faster); 1..9 and 0
// snap to dataset cameras 0..9; Space plays/pauses; P saves a screenshot; R starts/stops
// recording the camera path; T toggles the original and the last style, N steps to the next style,
// [ and ] lower and raise the blend factor; Esc quits. Input that ImGui wants (over the panel) is
// left to it.
#pragma once
#include <GLFW/glfw3.h>

#include <map>

namespace s4d::viewer {

struct InputFrame {
  double drag_dx = 0, drag_dy = 0;  // pixels, left button
  double pan_dx = 0, pan_dy = 0;    // pixels, right or middle button
  double scroll = 0;                // wheel steps
  double fly_forward = 0, fly_right = 0, fly_up = 0;  // -1..1 each (x4 with Shift)
  int snap_camera = -1;             // camera index from a number key
  bool toggle_play = false, screenshot = false, toggle_record = false, quit = false;
  bool toggle_original = false, next_style = false;  // T: original <-> the last style; N: the next style
  int blend_step = 0;               // [: -1, ]: +1 (steps of the blend factor)
};

class Input {
 public:
  // Installs the scroll callback; create it before ImGui's GLFW backend, which chains to it.
  explicit Input(GLFWwindow* window);
  InputFrame poll(bool mouse_to_imgui, bool keyboard_to_imgui);

 private:
  static void on_scroll(GLFWwindow* window, double dx, double dy);
  bool pressed(int key);  // went down since the last poll

  GLFWwindow* window_;
  double last_x_ = 0, last_y_ = 0;
  double scroll_ = 0;
  std::map<int, bool> down_;
};

}  // namespace s4d::viewer
