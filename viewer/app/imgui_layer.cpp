#include "imgui_layer.h"

#include <imgui.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_vulkan.h>

#include <stdexcept>

#include "s4d/engine/check.h"
#include "s4d/engine/recorder.h"

namespace s4d::viewer {

namespace {

// ImGui's backend reports every VkResult here; errors become the engine's VulkanError.
void check_imgui_vk(VkResult r) {
  if (r < 0) engine::throw_vk_error(r, "a Vulkan call in imgui_impl_vulkan", __FILE__, __LINE__);
}

bool queue_does_graphics(const engine::Context& ctx) {
  uint32_t count = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(ctx.physical_device(), &count, nullptr);
  std::vector<VkQueueFamilyProperties> families(count);
  vkGetPhysicalDeviceQueueFamilyProperties(ctx.physical_device(), &count, families.data());
  return (families[ctx.queue_family()].queueFlags & VK_QUEUE_GRAPHICS_BIT) != 0;
}

VkRenderPass make_render_pass(engine::Context& ctx, VkFormat format) {
  VkAttachmentDescription color{.format = format,
                                .samples = VK_SAMPLE_COUNT_1_BIT,
                                .loadOp = VK_ATTACHMENT_LOAD_OP_LOAD,  // the frame copied in before
                                .storeOp = VK_ATTACHMENT_STORE_OP_STORE,
                                .stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE,
                                .stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE,
                                .initialLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                                .finalLayout = VK_IMAGE_LAYOUT_PRESENT_SRC_KHR};
  VkAttachmentReference ref{0, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
  VkSubpassDescription subpass{.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS,
                               .colorAttachmentCount = 1,
                               .pColorAttachments = &ref};
  // The copy into the image happens before the pass loads it.
  VkSubpassDependency after_copy{.srcSubpass = VK_SUBPASS_EXTERNAL,
                                 .dstSubpass = 0,
                                 .srcStageMask = VK_PIPELINE_STAGE_TRANSFER_BIT,
                                 .dstStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT,
                                 .srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT,
                                 .dstAccessMask = VK_ACCESS_COLOR_ATTACHMENT_READ_BIT |
                                                  VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT};
  VkRenderPassCreateInfo ci{.sType = VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO,
                            .attachmentCount = 1,
                            .pAttachments = &color,
                            .subpassCount = 1,
                            .pSubpasses = &subpass,
                            .dependencyCount = 1,
                            .pDependencies = &after_copy};
  VkRenderPass pass = VK_NULL_HANDLE;
  S4D_VK_CHECK(vkCreateRenderPass(ctx.device(), &ci, nullptr, &pass));
  ctx.set_name(VK_OBJECT_TYPE_RENDER_PASS, reinterpret_cast<uint64_t>(pass), "viewer panel pass");
  return pass;
}

}  // namespace

ImGuiLayer::ImGuiLayer(engine::Context& ctx, GLFWwindow* window, const Swapchain& swapchain) : ctx_(&ctx) {
  if (!queue_does_graphics(ctx))
    throw std::runtime_error("the panel (Dear ImGui) draws with a graphics pipeline, but " + ctx.info().name +
                             "'s chosen compute queue has no graphics support");
  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini next to the user's files
  try {
    VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1};  // the font texture
    VkDescriptorPoolCreateInfo pci{.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO,
                                   .flags = VK_DESCRIPTOR_POOL_CREATE_FREE_DESCRIPTOR_SET_BIT,
                                   .maxSets = 1,
                                   .poolSizeCount = 1,
                                   .pPoolSizes = &size};
    S4D_VK_CHECK(vkCreateDescriptorPool(ctx.device(), &pci, nullptr, &pool_));
    render_pass_ = make_render_pass(ctx, swapchain.format());
    glfw_backend_ = ImGui_ImplGlfw_InitForVulkan(window, true);
    if (!glfw_backend_) throw std::runtime_error("ImGui's GLFW backend failed to start");
    ImGui_ImplVulkan_InitInfo info{};
    info.Instance = ctx.instance();
    info.PhysicalDevice = ctx.physical_device();
    info.Device = ctx.device();
    info.QueueFamily = ctx.queue_family();
    info.Queue = ctx.queue();
    info.DescriptorPool = pool_;
    info.MinImageCount = swapchain.min_image_count();
    info.ImageCount = swapchain.image_count();
    info.MSAASamples = VK_SAMPLE_COUNT_1_BIT;
    info.CheckVkResultFn = check_imgui_vk;
    vulkan_backend_ = ImGui_ImplVulkan_Init(&info, render_pass_);
    if (!vulkan_backend_) throw std::runtime_error("ImGui's Vulkan backend failed to start");
    engine::Recorder rec(ctx, "imgui font upload");
    if (!ImGui_ImplVulkan_CreateFontsTexture(rec.handle())) throw std::runtime_error("ImGui's font upload failed");
    ctx.run(std::move(rec));
    ImGui_ImplVulkan_DestroyFontUploadObjects();
    on_swapchain_recreated(swapchain);
  } catch (...) {
    release();
    throw;
  }
}

ImGuiLayer::~ImGuiLayer() { release(); }

void ImGuiLayer::release() {
  // Teardown cannot report failure; it goes on when the device is lost.
  (void)vkDeviceWaitIdle(ctx_->device());
  if (vulkan_backend_) ImGui_ImplVulkan_Shutdown();
  if (glfw_backend_) ImGui_ImplGlfw_Shutdown();
  vulkan_backend_ = glfw_backend_ = false;
  if (ImGui::GetCurrentContext()) ImGui::DestroyContext();
  destroy_framebuffers();
  if (render_pass_) vkDestroyRenderPass(ctx_->device(), render_pass_, nullptr);
  if (pool_) vkDestroyDescriptorPool(ctx_->device(), pool_, nullptr);
  render_pass_ = VK_NULL_HANDLE;
  pool_ = VK_NULL_HANDLE;
}

void ImGuiLayer::destroy_framebuffers() {
  for (VkFramebuffer f : framebuffers_) vkDestroyFramebuffer(ctx_->device(), f, nullptr);
  framebuffers_.clear();
}

void ImGuiLayer::on_swapchain_recreated(const Swapchain& swapchain) {
  destroy_framebuffers();
  ImGui_ImplVulkan_SetMinImageCount(swapchain.min_image_count());
  for (uint32_t i = 0; i < swapchain.image_count(); ++i) {
    const VkImageView view = swapchain.view(i);
    VkFramebufferCreateInfo ci{.sType = VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO,
                               .renderPass = render_pass_,
                               .attachmentCount = 1,
                               .pAttachments = &view,
                               .width = swapchain.extent().width,
                               .height = swapchain.extent().height,
                               .layers = 1};
    VkFramebuffer fb = VK_NULL_HANDLE;
    S4D_VK_CHECK(vkCreateFramebuffer(ctx_->device(), &ci, nullptr, &fb));
    framebuffers_.push_back(fb);
  }
}

void ImGuiLayer::new_frame() {
  ImGui_ImplVulkan_NewFrame();
  ImGui_ImplGlfw_NewFrame();
  ImGui::NewFrame();
}

void ImGuiLayer::skip_frame() { ImGui::EndFrame(); }

void ImGuiLayer::record(VkCommandBuffer cmd, uint32_t image, VkExtent2D extent) {
  ImGui::Render();
  VkRenderPassBeginInfo bi{.sType = VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO,
                           .renderPass = render_pass_,
                           .framebuffer = framebuffers_[image],
                           .renderArea = {{0, 0}, extent}};
  vkCmdBeginRenderPass(cmd, &bi, VK_SUBPASS_CONTENTS_INLINE);
  ImGui_ImplVulkan_RenderDrawData(ImGui::GetDrawData(), cmd);
  vkCmdEndRenderPass(cmd);
}

}  // namespace s4d::viewer
