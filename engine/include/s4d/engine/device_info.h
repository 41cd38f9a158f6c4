// What the engine knows about a physical device: identity, the features its kernels use, limits.
#pragma once
#include <vulkan/vulkan.h>

#include <cstdint>
#include <string>
#include <vector>

namespace s4d::engine {

struct DeviceInfo {
  uint32_t index = 0;  // position in vkEnumeratePhysicalDevices order (what S4D_DEVICE=<index> means)
  std::string name;
  VkPhysicalDeviceType type = VK_PHYSICAL_DEVICE_TYPE_OTHER;
  uint32_t api_version = 0;
  std::string driver_name;  // "llvmpipe", "NVIDIA", ...
  std::string driver_info;  // "Mesa 22.3.6 (LLVM 15.0.6)", ...
  uint32_t vendor_id = 0;
  uint32_t device_id = 0;

  // Features the kernels choose variants by.
  uint32_t subgroup_size = 0;
  uint32_t min_subgroup_size = 0;
  uint32_t max_subgroup_size = 0;
  bool subgroup_arithmetic = false;  // basic + arithmetic + vote + shuffle in compute shaders (required)
  bool float_atomic_add_buffer = false;
  bool float_atomic_add_shared = false;
  bool fp16_arithmetic = false;
  bool storage_16bit = false;
  bool int64 = false;
  bool push_descriptor = false;  // VK_KHR_push_descriptor (required)
  bool timeline_semaphore = false;  // required

  // Limits.
  uint32_t max_workgroup_count[3] = {0, 0, 0};
  uint32_t max_workgroup_size[3] = {0, 0, 0};
  uint32_t max_workgroup_invocations = 0;
  uint32_t max_shared_memory_bytes = 0;
  uint32_t max_push_constant_bytes = 0;
  uint64_t max_storage_buffer_range = 0;
  uint64_t min_storage_buffer_offset_alignment = 0;
  uint64_t max_memory_allocation_size = 0;
  uint64_t device_local_bytes = 0;  // size of the largest device-local heap

  // Timestamps on the compute queue.
  bool timestamps = false;
  float timestamp_period_ns = 0;
  uint32_t timestamp_valid_bits = 0;

  // Whether the engine can run on it, and if not, why.
  bool suitable = false;
  std::string unsuitable_reason;
  uint32_t compute_queue_family = 0;

  std::string type_name() const;
  std::string api_version_string() const;
};

// Ordering rank for automatic choice: discrete > integrated > virtual > CPU > other.
int device_type_rank(VkPhysicalDeviceType type);

// Reads identity, features and limits of a physical device.
DeviceInfo query_device_info(VkPhysicalDevice device, uint32_t index);

// Chooses among `devices` (all from one instance): the S4D_DEVICE override when `override_spec` is
// non-empty (an index or a case-insensitive substring of the name), else the best suitable device.
// Throws std::runtime_error naming the devices seen when nothing fits.
const DeviceInfo& choose_device(const std::vector<DeviceInfo>& devices, const std::string& override_spec);

}  // namespace s4d::engine
