// The Vulkan context: instance, chosen device, compute queue, submission timeline, deferred
// destruction, validation-message accounting and the pipeline cache. One per process is the norm
// (tests share one); it outlives every resource made from it.
#pragma once
#include <vulkan/vulkan.h>

#include <algorithm>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <vector>

#include "s4d/engine/device_info.h"

namespace s4d::engine {

class Buffer;
class Pipeline;
class Recorder;
class StageTimer;

struct ContextOptions {
  bool validation = false;  // enable VK_LAYER_KHRONOS_validation and count its errors
  std::string device;       // S4D_DEVICE: index or name substring; empty = automatic choice
  // Map storage buffers into host memory on CPU and UMA devices (uploads become memcpy). Off: every
  // upload and readback goes through a staging buffer, as on a discrete GPU (tests use this).
  bool map_device_memory = true;
  // Caps the 1-D workgroup count before dispatches split into a 2-D grid (0: the device limit).
  // Lets tests reach the split path with small dispatches.
  uint32_t max_groups_x = 0;
  // Presentation, for the viewer; the engine itself knows no windowing library. Extra instance
  // extensions (VK_KHR_surface and the window system's, as the windowing library names them) and
  // device extensions (VK_KHR_swapchain); a missing one is an error naming it. When `can_present`
  // is set, the context's queue is a compute queue family for which it returns true, and devices
  // without one are unsuitable ("cannot present to the window").
  std::vector<std::string> instance_extensions;
  std::vector<std::string> device_extensions;
  std::function<bool(VkInstance, VkPhysicalDevice, uint32_t queue_family)> can_present;
  // Reads S4D_VALIDATION (1/0) and S4D_DEVICE.
  static ContextOptions from_env();
};

struct SpecConstant {
  uint32_t id;
  uint32_t value;
  bool operator<(const SpecConstant& o) const { return id < o.id || (id == o.id && value < o.value); }
};

// Binary semaphores a submission waits on and signals besides the context's timeline (swapchain
// image acquisition and presentation).
struct SubmitSync {
  VkSemaphore wait = VK_NULL_HANDLE;
  VkPipelineStageFlags wait_stage = 0;  // stages that wait for `wait`
  VkSemaphore signal = VK_NULL_HANDLE;
};

class Context {
 public:
  explicit Context(const ContextOptions& options = ContextOptions::from_env());
  ~Context();
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;

  const DeviceInfo& info() const { return info_; }
  uint32_t max_groups_x() const { return max_groups_x_; }
  VkInstance instance() const { return instance_; }
  VkPhysicalDevice physical_device() const { return physical_; }
  VkDevice device() const { return device_; }
  VkQueue queue() const { return queue_; }
  uint32_t queue_family() const { return info_.compute_queue_family; }
  VkCommandPool command_pool() const { return command_pool_; }

  // Submits the recorded commands; returns the timeline value that marks their completion.
  uint64_t submit(Recorder&& recorder, const SubmitSync& sync = {});
  // Blocks until the submission with this timeline value has completed, then frees what it retired.
  void wait(uint64_t value);
  // submit + wait.
  void run(Recorder&& recorder) { wait(submit(std::move(recorder))); }
  // Waits for every submission so far.
  void wait_idle();
  // Submissions so far, and host waits that blocked on one not yet seen complete (uploads and
  // downloads through staging count too): what a frame or training step costs in round trips.
  uint64_t submissions() const { return submitted_; }
  uint64_t host_waits() const { return host_waits_; }

  // Defers `destroy` until every submission made so far has completed (Granite-style retire list).
  void retire(std::function<void()> destroy);

  // Copies between host memory and a buffer. Waits for pending submissions first, so the data seen
  // is the result of all work submitted before the call.
  void upload(Buffer& dst, const void* data, size_t bytes, size_t dst_offset = 0);
  void download(const Buffer& src, void* data, size_t bytes, size_t src_offset = 0);
  template <class T>
  void upload(Buffer& dst, std::span<const T> values, size_t dst_offset_elems = 0) {
    upload(dst, values.data(), values.size_bytes(), dst_offset_elems * sizeof(T));
  }
  template <class T>
  std::vector<T> download(const Buffer& src, size_t count, size_t src_offset_elems = 0) {
    std::vector<T> out(count);
    download(src, out.data(), count * sizeof(T), src_offset_elems * sizeof(T));
    return out;
  }

  // The compute pipeline for a SPIR-V module with the given specialization constants, created on
  // first use and cached by (name, constants). References stay valid for the context's lifetime.
  const Pipeline& pipeline(const std::string& name, std::span<const uint32_t> spirv,
                           const std::vector<SpecConstant>& spec = {});

  // Memory type index with all `required` flags, preferring `preferred` ones; throws if none.
  uint32_t memory_type(uint32_t type_bits, VkMemoryPropertyFlags required, VkMemoryPropertyFlags preferred) const;
  // True where device-local memory is also host-visible and cheap to map (CPU and UMA devices).
  bool unified_memory() const { return unified_memory_; }

  // Debug name for any Vulkan object (VK_EXT_debug_utils); a no-op when the extension is absent.
  void set_name(VkObjectType type, uint64_t handle, const std::string& name) const;
  bool debug_utils() const { return set_object_name_ != nullptr; }
  PFN_vkCmdBeginDebugUtilsLabelEXT cmd_begin_label() const { return cmd_begin_label_; }
  PFN_vkCmdEndDebugUtilsLabelEXT cmd_end_label() const { return cmd_end_label_; }
  PFN_vkCmdPushDescriptorSetKHR cmd_push_descriptor_set() const { return cmd_push_descriptor_set_; }

  // Device memory held by buffers of this context, and its peak since creation or the last reset
  // (per-stage peaks in reports).
  void count_memory(int64_t bytes) {
    memory_in_use_ = static_cast<uint64_t>(static_cast<int64_t>(memory_in_use_) + bytes);
    memory_peak_ = std::max(memory_peak_, memory_in_use_);
  }
  uint64_t memory_in_use() const { return memory_in_use_; }
  uint64_t memory_peak() const { return memory_peak_; }
  void reset_memory_peak() { memory_peak_ = memory_in_use_; }

  // Validation errors reported so far (only counted when options.validation is on).
  uint64_t validation_error_count() const;
  std::vector<std::string> take_validation_messages();
  bool validation_enabled() const { return validation_; }

  // The last dispatch labels recorded, reported when the device is lost.
  void note_op(const std::string& name);

  // Throws VulkanError(VK_ERROR_DEVICE_LOST) naming the device, `where` and the last recorded
  // operations. For callers that meet device loss outside submit/wait (presentation).
  [[noreturn]] void device_lost(const char* where);

  // The stage timer installed on this context (StageTimer installs and removes itself), or nullptr.
  StageTimer* stage_timer() const { return stage_timer_; }
  void set_stage_timer(StageTimer* timer) { stage_timer_ = timer; }

  // Recorders still recording: objects retired meanwhile may be used by their coming submission.
  void recorder_opened() { ++open_recorders_; }
  void recorder_closed() { --open_recorders_; }

 private:
  friend class Recorder;
  void create_instance();
  void create_device();
  void collect_retired();
  void require_presentation(std::vector<DeviceInfo>& infos, const std::vector<VkPhysicalDevice>& handles) const;
  static VKAPI_ATTR VkBool32 VKAPI_CALL on_debug_message(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                         VkDebugUtilsMessageTypeFlagsEXT types,
                                                         const VkDebugUtilsMessengerCallbackDataEXT* data,
                                                         void* user);

  bool validation_ = false;
  std::string device_spec_;
  std::vector<std::string> instance_extensions_, device_extensions_;
  std::function<bool(VkInstance, VkPhysicalDevice, uint32_t)> can_present_;
  bool map_device_memory_ = true;
  uint32_t max_groups_x_ = 0;
  VkInstance instance_ = VK_NULL_HANDLE;
  VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
  VkPhysicalDevice physical_ = VK_NULL_HANDLE;
  DeviceInfo info_;
  VkDevice device_ = VK_NULL_HANDLE;
  VkQueue queue_ = VK_NULL_HANDLE;
  VkCommandPool command_pool_ = VK_NULL_HANDLE;
  VkSemaphore timeline_ = VK_NULL_HANDLE;
  uint64_t submitted_ = 0;
  uint32_t open_recorders_ = 0;
  uint64_t completed_ = 0;
  uint64_t host_waits_ = 0;
  VkPhysicalDeviceMemoryProperties memory_props_{};
  bool unified_memory_ = false;
  uint64_t memory_in_use_ = 0, memory_peak_ = 0;
  StageTimer* stage_timer_ = nullptr;

  struct Retired {
    // Timeline value that must complete first; kAfterOpenRecorders while recorders that were open
    // when it was retired are still open (their submissions' values are not known yet).
    uint64_t after;
    std::function<void()> destroy;
  };
  static constexpr uint64_t kAfterOpenRecorders = UINT64_MAX;
  std::deque<Retired> retired_;

  std::map<std::pair<std::string, std::vector<SpecConstant>>, std::unique_ptr<Pipeline>> pipelines_;

  mutable std::mutex messages_mutex_;
  uint64_t validation_errors_ = 0;
  std::vector<std::string> validation_messages_;
  std::deque<std::string> recent_ops_;

  PFN_vkSetDebugUtilsObjectNameEXT set_object_name_ = nullptr;
  PFN_vkCmdBeginDebugUtilsLabelEXT cmd_begin_label_ = nullptr;
  PFN_vkCmdEndDebugUtilsLabelEXT cmd_end_label_ = nullptr;
  PFN_vkCmdPushDescriptorSetKHR cmd_push_descriptor_set_ = nullptr;
};

// Every Vulkan device the loader reports, with features, limits and suitability (creates a
// short-lived instance; no logical device).
std::vector<DeviceInfo> list_devices();

}  // namespace s4d::engine
