// The GLFW window: no client API (Vulkan draws), the instance extensions and presentation test the
// engine's context needs, and the surface. The only place that talks to GLFW besides input and
// the ImGui backend.
#pragma once
#include <vulkan/vulkan.h>

#include <GLFW/glfw3.h>

#include <string>
#include <utility>
#include <vector>

namespace s4d::viewer {

class Window {
 public:
  // Throws std::runtime_error with GLFW's reason when there is no display or no Vulkan loader.
  Window(const std::string& title, int width, int height);
  ~Window();
  Window(const Window&) = delete;
  Window& operator=(const Window&) = delete;

  GLFWwindow* handle() const { return window_; }
  // VK_KHR_surface and the window system's surface extension.
  std::vector<std::string> instance_extensions() const;
  // Whether a queue family of a device can present to this display.
  static bool can_present(VkInstance instance, VkPhysicalDevice device, uint32_t queue_family);
  VkSurfaceKHR create_surface(VkInstance instance) const;
  // Framebuffer size in pixels; (0, 0) while minimised.
  std::pair<int, int> framebuffer_size() const;
  bool should_close() const { return glfwWindowShouldClose(window_) != 0; }

 private:
  GLFWwindow* window_ = nullptr;
};

}  // namespace s4d::viewer
