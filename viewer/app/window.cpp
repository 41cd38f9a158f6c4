#include "window.h"

#include <stdexcept>

#include "s4d/engine/check.h"

namespace s4d::viewer {

namespace {

std::string g_last_glfw_error;  // GLFW reports errors through a callback; the last one explains a failure

void on_glfw_error(int /*code*/, const char* description) { g_last_glfw_error = description ? description : "?"; }

}  // namespace

Window::Window(const std::string& title, int width, int height) {
  glfwSetErrorCallback(on_glfw_error);
  if (!glfwInit())
    throw std::runtime_error("cannot open a window (" + g_last_glfw_error +
                             "); run it on a desktop or under xvfb-run, or capture headless with --screenshot");
  if (!glfwVulkanSupported()) {
    glfwTerminate();
    throw std::runtime_error("GLFW finds no Vulkan loader or no surface support (" + g_last_glfw_error + ")");
  }
  glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
  window_ = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
  if (!window_) {
    glfwTerminate();
    throw std::runtime_error("cannot create a window: " + g_last_glfw_error);
  }
}

Window::~Window() {
  glfwDestroyWindow(window_);
  glfwTerminate();
}

std::vector<std::string> Window::instance_extensions() const {
  uint32_t count = 0;
  const char** names = glfwGetRequiredInstanceExtensions(&count);
  if (!names) throw std::runtime_error("GLFW names no Vulkan surface extensions: " + g_last_glfw_error);
  return std::vector<std::string>(names, names + count);
}

bool Window::can_present(VkInstance instance, VkPhysicalDevice device, uint32_t queue_family) {
  return glfwGetPhysicalDevicePresentationSupport(instance, device, queue_family) == GLFW_TRUE;
}

VkSurfaceKHR Window::create_surface(VkInstance instance) const {
  VkSurfaceKHR surface = VK_NULL_HANDLE;
  S4D_VK_CHECK_CTX(glfwCreateWindowSurface(instance, window_, nullptr, &surface),
                   "creating the window's surface (" + g_last_glfw_error + ")");
  return surface;
}

std::pair<int, int> Window::framebuffer_size() const {
  int w = 0, h = 0;
  glfwGetFramebufferSize(window_, &w, &h);
  return {w, h};
}

}  // namespace s4d::viewer
