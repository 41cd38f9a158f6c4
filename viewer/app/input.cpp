#include "input.h"

namespace s4d::viewer {

Input::Input(GLFWwindow* window) : window_(window) {
  glfwSetWindowUserPointer(window, this);
  glfwSetScrollCallback(window, &Input::on_scroll);
  glfwGetCursorPos(window, &last_x_, &last_y_);
}

void Input::on_scroll(GLFWwindow* window, double /*dx*/, double dy) {
  static_cast<Input*>(glfwGetWindowUserPointer(window))->scroll_ += dy;
}

bool Input::pressed(int key) {
  const bool now = glfwGetKey(window_, key) == GLFW_PRESS;
  const bool was = down_[key];
  down_[key] = now;
  return now && !was;
}

InputFrame Input::poll(bool mouse_to_imgui, bool keyboard_to_imgui) {
  InputFrame f;
  double x = 0, y = 0;
  glfwGetCursorPos(window_, &x, &y);
  const double dx = x - last_x_, dy = y - last_y_;
  last_x_ = x, last_y_ = y;
  if (!mouse_to_imgui) {
    if (glfwGetMouseButton(window_, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS) f.drag_dx = dx, f.drag_dy = dy;
    if (glfwGetMouseButton(window_, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS ||
        glfwGetMouseButton(window_, GLFW_MOUSE_BUTTON_MIDDLE) == GLFW_PRESS)
      f.pan_dx = dx, f.pan_dy = dy;
    f.scroll = scroll_;
  }
  scroll_ = 0;
  // Edge detection runs every frame so a key held while over the panel does not fire later.
  const bool play = pressed(GLFW_KEY_SPACE), shot = pressed(GLFW_KEY_P), record = pressed(GLFW_KEY_R);
  const bool toggle_original = pressed(GLFW_KEY_T), next_style = pressed(GLFW_KEY_N);
  const int blend_step = (pressed(GLFW_KEY_RIGHT_BRACKET) ? 1 : 0) - (pressed(GLFW_KEY_LEFT_BRACKET) ? 1 : 0);
  int snap = -1;
  for (int k = 0; k <= 9; ++k)
    if (pressed(GLFW_KEY_0 + k)) snap = k == 0 ? 9 : k - 1;
  if (keyboard_to_imgui) return f;
  f.toggle_play = play, f.screenshot = shot, f.toggle_record = record, f.snap_camera = snap;
  f.toggle_original = toggle_original, f.next_style = next_style, f.blend_step = blend_step;
  f.quit = glfwGetKey(window_, GLFW_KEY_ESCAPE) == GLFW_PRESS;
  auto held = [&](int key) { return glfwGetKey(window_, key) == GLFW_PRESS ? 1.0 : 0.0; };
  const double boost = held(GLFW_KEY_LEFT_SHIFT) > 0 || held(GLFW_KEY_RIGHT_SHIFT) > 0 ? 4.0 : 1.0;
  f.fly_forward = boost * (held(GLFW_KEY_W) - held(GLFW_KEY_S));
  f.fly_right = boost * (held(GLFW_KEY_D) - held(GLFW_KEY_A));
  f.fly_up = boost * (held(GLFW_KEY_E) - held(GLFW_KEY_Q));
  return f;
}

}  // namespace s4d::viewer
