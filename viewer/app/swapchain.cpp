#include "swapchain.h"

#include <algorithm>
#include <stdexcept>

#include "s4d/engine/check.h"

namespace s4d::viewer {

namespace {

// 8-bit formats whose bytes present_pack writes. A copy moves bytes unchanged, so an _SRGB format
// shows the same colours as _UNORM; UNORM is preferred because ImGui blends in it as designed.
VkSurfaceFormatKHR choose_format(VkPhysicalDevice device, VkSurfaceKHR surface) {
  uint32_t count = 0;
  S4D_VK_CHECK(vkGetPhysicalDeviceSurfaceFormatsKHR(device, surface, &count, nullptr));
  std::vector<VkSurfaceFormatKHR> formats(count);
  S4D_VK_CHECK(vkGetPhysicalDeviceSurfaceFormatsKHR(device, surface, &count, formats.data()));
  for (VkFormat wanted : {VK_FORMAT_B8G8R8A8_UNORM, VK_FORMAT_R8G8B8A8_UNORM, VK_FORMAT_B8G8R8A8_SRGB,
                          VK_FORMAT_R8G8B8A8_SRGB})
    for (const VkSurfaceFormatKHR& f : formats)
      if (f.format == wanted) return f;
  throw std::runtime_error("the window offers no 8-bit RGBA or BGRA swapchain format");
}

VkSemaphore make_semaphore(engine::Context& ctx, const char* name) {
  VkSemaphoreCreateInfo ci{.sType = VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
  VkSemaphore s = VK_NULL_HANDLE;
  S4D_VK_CHECK(vkCreateSemaphore(ctx.device(), &ci, nullptr, &s));
  ctx.set_name(VK_OBJECT_TYPE_SEMAPHORE, reinterpret_cast<uint64_t>(s), name);
  return s;
}

}  // namespace

Swapchain::Swapchain(engine::Context& ctx, VkSurfaceKHR surface) : ctx_(&ctx), surface_(surface) {
  try {
    VkBool32 supported = VK_FALSE;
    S4D_VK_CHECK(vkGetPhysicalDeviceSurfaceSupportKHR(ctx.physical_device(), ctx.queue_family(), surface, &supported));
    if (!supported) throw std::runtime_error(ctx.info().name + " cannot present to this window from its compute queue");
    format_ = choose_format(ctx.physical_device(), surface);
    acquired_ = make_semaphore(ctx, "viewer image acquired");
  } catch (...) {
    vkDestroySurfaceKHR(ctx.instance(), surface_, nullptr);
    throw;
  }
}

Swapchain::~Swapchain() {
  // A destructor cannot report failure; teardown goes on when the device is lost.
  (void)vkDeviceWaitIdle(ctx_->device());
  destroy_images();
  for (VkSemaphore s : rendered_) vkDestroySemaphore(ctx_->device(), s, nullptr);
  if (swapchain_) vkDestroySwapchainKHR(ctx_->device(), swapchain_, nullptr);
  if (acquired_) vkDestroySemaphore(ctx_->device(), acquired_, nullptr);
  vkDestroySurfaceKHR(ctx_->instance(), surface_, nullptr);
}

PixelOrder Swapchain::pixel_order() const {
  return format_.format == VK_FORMAT_B8G8R8A8_UNORM || format_.format == VK_FORMAT_B8G8R8A8_SRGB ? PixelOrder::bgra
                                                                                                : PixelOrder::rgba;
}

void Swapchain::destroy_images() {
  for (VkImageView v : views_) vkDestroyImageView(ctx_->device(), v, nullptr);
  views_.clear();
  images_.clear();
}

void Swapchain::recreate(uint32_t width, uint32_t height) {
  // Also waits for presentation, which may still wait on a "rendered" semaphore.
  S4D_VK_CHECK(vkDeviceWaitIdle(ctx_->device()));
  ctx_->wait_idle();
  VkSurfaceCapabilitiesKHR caps{};
  S4D_VK_CHECK(vkGetPhysicalDeviceSurfaceCapabilitiesKHR(ctx_->physical_device(), surface_, &caps));
  const VkImageUsageFlags usage = VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT;
  if ((caps.supportedUsageFlags & usage) != usage)
    throw std::runtime_error("the window's swapchain images cannot be copied into (no TRANSFER_DST usage) on " +
                             ctx_->info().name);
  if (caps.currentExtent.width != UINT32_MAX) {
    extent_ = caps.currentExtent;
  } else {
    extent_ = {std::clamp(width, caps.minImageExtent.width, caps.maxImageExtent.width),
               std::clamp(height, caps.minImageExtent.height, caps.maxImageExtent.height)};
  }
  min_images_ = caps.minImageCount + 1;
  if (caps.maxImageCount > 0) min_images_ = std::min(min_images_, caps.maxImageCount);

  const VkSwapchainKHR old = swapchain_;
  VkSwapchainCreateInfoKHR ci{.sType = VK_STRUCTURE_TYPE_SWAPCHAIN_CREATE_INFO_KHR,
                              .surface = surface_,
                              .minImageCount = min_images_,
                              .imageFormat = format_.format,
                              .imageColorSpace = format_.colorSpace,
                              .imageExtent = extent_,
                              .imageArrayLayers = 1,
                              .imageUsage = usage,
                              .imageSharingMode = VK_SHARING_MODE_EXCLUSIVE,
                              .preTransform = caps.currentTransform,
                              .compositeAlpha = VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR,
                              .presentMode = VK_PRESENT_MODE_FIFO_KHR,  // the one mode every driver has
                              .clipped = VK_TRUE,
                              .oldSwapchain = old};
  if (!(caps.supportedCompositeAlpha & VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR))
    ci.compositeAlpha = VK_COMPOSITE_ALPHA_INHERIT_BIT_KHR;
  S4D_VK_CHECK_CTX(vkCreateSwapchainKHR(ctx_->device(), &ci, nullptr, &swapchain_), "creating the swapchain");
  destroy_images();
  if (old) vkDestroySwapchainKHR(ctx_->device(), old, nullptr);

  uint32_t count = 0;
  S4D_VK_CHECK(vkGetSwapchainImagesKHR(ctx_->device(), swapchain_, &count, nullptr));
  images_.resize(count);
  S4D_VK_CHECK(vkGetSwapchainImagesKHR(ctx_->device(), swapchain_, &count, images_.data()));
  for (uint32_t i = 0; i < count; ++i) {
    VkImageViewCreateInfo vi{.sType = VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO,
                             .image = images_[i],
                             .viewType = VK_IMAGE_VIEW_TYPE_2D,
                             .format = format_.format,
                             .subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1}};
    VkImageView view = VK_NULL_HANDLE;
    S4D_VK_CHECK(vkCreateImageView(ctx_->device(), &vi, nullptr, &view));
    views_.push_back(view);
  }
  // Semaphores are kept across recreation (a present may still hold one); only missing ones are made.
  while (rendered_.size() < count) rendered_.push_back(make_semaphore(*ctx_, "viewer image rendered"));
}

std::optional<uint32_t> Swapchain::acquire() {
  uint32_t index = 0;
  const VkResult r = vkAcquireNextImageKHR(ctx_->device(), swapchain_, UINT64_MAX, acquired_, VK_NULL_HANDLE, &index);
  if (r == VK_ERROR_OUT_OF_DATE_KHR) return std::nullopt;
  if (r == VK_ERROR_DEVICE_LOST) ctx_->device_lost("vkAcquireNextImageKHR");
  S4D_VK_CHECK(r);  // VK_SUBOPTIMAL_KHR still gives an image; present() reports it
  return index;
}

bool Swapchain::present(uint32_t image) {
  VkPresentInfoKHR pi{.sType = VK_STRUCTURE_TYPE_PRESENT_INFO_KHR,
                      .waitSemaphoreCount = 1,
                      .pWaitSemaphores = &rendered_[image],
                      .swapchainCount = 1,
                      .pSwapchains = &swapchain_,
                      .pImageIndices = &image};
  const VkResult r = vkQueuePresentKHR(ctx_->queue(), &pi);
  if (r == VK_ERROR_OUT_OF_DATE_KHR || r == VK_SUBOPTIMAL_KHR) return false;
  if (r == VK_ERROR_DEVICE_LOST) ctx_->device_lost("vkQueuePresentKHR");
  S4D_VK_CHECK(r);
  return true;
}

}  // namespace s4d::viewer
