// The Dear ImGui panel over the frame: Debian's libimgui-dev ships the GLFW and Vulkan backends
// (imgui_impl_glfw, imgui_impl_vulkan) in libimgui.a, so the panel is drawn by ImGui's own
// graphics pipeline in a render pass that loads the copied frame and ends in PRESENT_SRC. That
// needs the context's queue to do graphics as well as compute (lavapipe's and every desktop GPU's
// first queue family does); where it does not, the constructor says so.
#pragma once
#include <vulkan/vulkan.h>

#include <GLFW/glfw3.h>

#include <vector>

#include "s4d/engine/context.h"
#include "swapchain.h"

namespace s4d::viewer {

class ImGuiLayer {
 public:
  // Installs ImGui's GLFW callbacks (chaining to those already set) and uploads the font.
  ImGuiLayer(engine::Context& ctx, GLFWwindow* window, const Swapchain& swapchain);
  ~ImGuiLayer();
  ImGuiLayer(const ImGuiLayer&) = delete;
  ImGuiLayer& operator=(const ImGuiLayer&) = delete;

  // Framebuffers for the swapchain's current images.
  void on_swapchain_recreated(const Swapchain& swapchain);
  // Starts a frame; panel code runs between this and record().
  void new_frame();
  // Ends the frame and records its draw into `cmd`: a render pass over swapchain image `image`,
  // which must be in TRANSFER_DST_OPTIMAL after a copy; leaves it in PRESENT_SRC_KHR.
  void record(VkCommandBuffer cmd, uint32_t image, VkExtent2D extent);
  // Ends a frame that will not be drawn (the swapchain was out of date).
  void skip_frame();

 private:
  void destroy_framebuffers();
  void release();  // everything the constructor made, in reverse order

  engine::Context* ctx_;
  VkDescriptorPool pool_ = VK_NULL_HANDLE;
  VkRenderPass render_pass_ = VK_NULL_HANDLE;
  std::vector<VkFramebuffer> framebuffers_;
  bool vulkan_backend_ = false, glfw_backend_ = false;
};

}  // namespace s4d::viewer
