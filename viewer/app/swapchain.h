// The window's swapchain: images the frame is copied into (transfer destination) and ImGui draws
// over (colour attachment), recreated on resize; per-image "rendered" semaphores and one
// "acquired" semaphore (the frame loop waits for the previous frame before acquiring).
#pragma once
#include <vulkan/vulkan.h>

#include <cstdint>
#include <optional>
#include <vector>

#include "s4d/engine/context.h"
#include "s4d/viewer/frame_renderer.h"

namespace s4d::viewer {

class Swapchain {
 public:
  // Takes ownership of `surface`. Throws when the device cannot copy into or draw on its images.
  Swapchain(engine::Context& ctx, VkSurfaceKHR surface);
  ~Swapchain();
  Swapchain(const Swapchain&) = delete;
  Swapchain& operator=(const Swapchain&) = delete;

  // (Re)creates the images for a framebuffer of width x height (the surface's extent wins when it
  // fixes one). Waits for the device first.
  void recreate(uint32_t width, uint32_t height);
  // The next image, its "acquired" semaphore signalled when it is ready; nullopt when the
  // swapchain is out of date (recreate, then try again).
  std::optional<uint32_t> acquire();
  // Queues `image` for presentation after its "rendered" semaphore; false when the swapchain is
  // out of date or suboptimal (recreate before the next frame).
  bool present(uint32_t image);

  VkSemaphore acquired() const { return acquired_; }
  VkSemaphore rendered(uint32_t image) const { return rendered_[image]; }
  VkFormat format() const { return format_.format; }
  PixelOrder pixel_order() const;
  VkExtent2D extent() const { return extent_; }
  uint32_t min_image_count() const { return min_images_; }
  uint32_t image_count() const { return static_cast<uint32_t>(images_.size()); }
  VkImage image(uint32_t i) const { return images_[i]; }
  VkImageView view(uint32_t i) const { return views_[i]; }

 private:
  void destroy_images();

  engine::Context* ctx_;
  VkSurfaceKHR surface_;
  VkSurfaceFormatKHR format_{};
  VkSwapchainKHR swapchain_ = VK_NULL_HANDLE;
  VkExtent2D extent_{};
  uint32_t min_images_ = 2;
  std::vector<VkImage> images_;
  std::vector<VkImageView> views_;
  std::vector<VkSemaphore> rendered_;
  VkSemaphore acquired_ = VK_NULL_HANDLE;
};

}  // namespace s4d::viewer
