#include "s4d/engine/device_info.h"

#include "s4d/engine/check.h"

#include <algorithm>
#include <cctype>
#include <cstring>
#include <sstream>
#include <stdexcept>

namespace s4d::engine {

namespace {

bool has_extension(VkPhysicalDevice device, const char* name) {
  uint32_t count = 0;
  S4D_VK_CHECK(vkEnumerateDeviceExtensionProperties(device, nullptr, &count, nullptr));
  std::vector<VkExtensionProperties> exts(count);
  S4D_VK_CHECK(vkEnumerateDeviceExtensionProperties(device, nullptr, &count, exts.data()));
  exts.resize(count);
  return std::any_of(exts.begin(), exts.end(),
                     [&](const VkExtensionProperties& e) { return std::strcmp(e.extensionName, name) == 0; });
}

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

}  // namespace

std::string DeviceInfo::type_name() const {
  switch (type) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU:
      return "discrete GPU";
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU:
      return "integrated GPU";
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU:
      return "virtual GPU";
    case VK_PHYSICAL_DEVICE_TYPE_CPU:
      return "CPU";
    default:
      return "other";
  }
}

std::string DeviceInfo::api_version_string() const {
  std::ostringstream s;
  s << VK_API_VERSION_MAJOR(api_version) << "." << VK_API_VERSION_MINOR(api_version) << "."
    << VK_API_VERSION_PATCH(api_version);
  return s.str();
}

int device_type_rank(VkPhysicalDeviceType type) {
  switch (type) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU:
      return 4;
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU:
      return 3;
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU:
      return 2;
    case VK_PHYSICAL_DEVICE_TYPE_CPU:
      return 1;
    default:
      return 0;
  }
}

DeviceInfo query_device_info(VkPhysicalDevice device, uint32_t index) {
  DeviceInfo info;
  info.index = index;

  VkPhysicalDeviceDriverProperties driver{.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES};
  VkPhysicalDeviceSubgroupSizeControlProperties sg_control{
      .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_SIZE_CONTROL_PROPERTIES, .pNext = &driver};
  VkPhysicalDeviceSubgroupProperties subgroup{.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_PROPERTIES,
                                              .pNext = &sg_control};
  VkPhysicalDeviceProperties2 props{.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2, .pNext = &subgroup};
  vkGetPhysicalDeviceProperties2(device, &props);
  const VkPhysicalDeviceLimits& lim = props.properties.limits;

  info.name = props.properties.deviceName;
  info.type = props.properties.deviceType;
  info.api_version = props.properties.apiVersion;
  info.vendor_id = props.properties.vendorID;
  info.device_id = props.properties.deviceID;
  info.driver_name = driver.driverName;
  info.driver_info = driver.driverInfo;

  info.subgroup_size = subgroup.subgroupSize;
  const bool size_control = info.api_version >= VK_API_VERSION_1_3 || has_extension(device, "VK_EXT_subgroup_size_control");
  info.min_subgroup_size = size_control ? sg_control.minSubgroupSize : subgroup.subgroupSize;
  info.max_subgroup_size = size_control ? sg_control.maxSubgroupSize : subgroup.subgroupSize;
  const VkSubgroupFeatureFlags needed_ops =
      VK_SUBGROUP_FEATURE_BASIC_BIT | VK_SUBGROUP_FEATURE_ARITHMETIC_BIT | VK_SUBGROUP_FEATURE_VOTE_BIT |
      VK_SUBGROUP_FEATURE_SHUFFLE_BIT;  // raster_bwd's reduce-scatter
  info.subgroup_arithmetic = (subgroup.supportedStages & VK_SHADER_STAGE_COMPUTE_BIT) &&
                             (subgroup.supportedOperations & needed_ops) == needed_ops;

  VkPhysicalDeviceShaderAtomicFloatFeaturesEXT atomic_float{
      .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SHADER_ATOMIC_FLOAT_FEATURES_EXT};
  const bool has_atomic_float_ext = has_extension(device, VK_EXT_SHADER_ATOMIC_FLOAT_EXTENSION_NAME);
  VkPhysicalDeviceVulkan12Features f12{.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES,
                                       .pNext = has_atomic_float_ext ? &atomic_float : nullptr};
  VkPhysicalDeviceVulkan11Features f11{.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_1_FEATURES, .pNext = &f12};
  VkPhysicalDeviceFeatures2 features{.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, .pNext = &f11};
  if (info.api_version >= VK_API_VERSION_1_2) vkGetPhysicalDeviceFeatures2(device, &features);
  info.float_atomic_add_buffer = has_atomic_float_ext && atomic_float.shaderBufferFloat32AtomicAdd;
  info.float_atomic_add_shared = has_atomic_float_ext && atomic_float.shaderSharedFloat32AtomicAdd;
  info.fp16_arithmetic = f12.shaderFloat16;
  info.storage_16bit = f11.storageBuffer16BitAccess;
  info.int64 = features.features.shaderInt64;
  info.timeline_semaphore = f12.timelineSemaphore;
  info.push_descriptor = has_extension(device, VK_KHR_PUSH_DESCRIPTOR_EXTENSION_NAME);

  for (int i = 0; i < 3; ++i) {
    info.max_workgroup_count[i] = lim.maxComputeWorkGroupCount[i];
    info.max_workgroup_size[i] = lim.maxComputeWorkGroupSize[i];
  }
  info.max_workgroup_invocations = lim.maxComputeWorkGroupInvocations;
  info.max_shared_memory_bytes = lim.maxComputeSharedMemorySize;
  info.max_push_constant_bytes = lim.maxPushConstantsSize;
  info.max_storage_buffer_range = lim.maxStorageBufferRange;
  info.min_storage_buffer_offset_alignment = lim.minStorageBufferOffsetAlignment;

  VkPhysicalDeviceMaintenance3Properties m3{.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MAINTENANCE_3_PROPERTIES};
  VkPhysicalDeviceProperties2 props_m3{.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2, .pNext = &m3};
  vkGetPhysicalDeviceProperties2(device, &props_m3);
  info.max_memory_allocation_size = m3.maxMemoryAllocationSize;

  VkPhysicalDeviceMemoryProperties mem;
  vkGetPhysicalDeviceMemoryProperties(device, &mem);
  for (uint32_t h = 0; h < mem.memoryHeapCount; ++h)
    if (mem.memoryHeaps[h].flags & VK_MEMORY_HEAP_DEVICE_LOCAL_BIT)
      info.device_local_bytes = std::max<uint64_t>(info.device_local_bytes, mem.memoryHeaps[h].size);

  uint32_t qcount = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(device, &qcount, nullptr);
  std::vector<VkQueueFamilyProperties> queues(qcount);
  vkGetPhysicalDeviceQueueFamilyProperties(device, &qcount, queues.data());
  // Prefer a queue family that also does graphics: the viewer presents from the same queue.
  int family = -1;
  for (uint32_t q = 0; q < qcount; ++q) {
    if (!(queues[q].queueFlags & VK_QUEUE_COMPUTE_BIT)) continue;
    if (family < 0 || ((queues[q].queueFlags & VK_QUEUE_GRAPHICS_BIT) &&
                       !(queues[static_cast<uint32_t>(family)].queueFlags & VK_QUEUE_GRAPHICS_BIT)))
      family = static_cast<int>(q);
  }
  const bool has_compute = family >= 0;
  if (has_compute) {
    info.compute_queue_family = static_cast<uint32_t>(family);
    info.timestamp_valid_bits = queues[info.compute_queue_family].timestampValidBits;
    info.timestamps = info.timestamp_valid_bits > 0 && lim.timestampPeriod > 0;
  }
  info.timestamp_period_ns = lim.timestampPeriod;

  std::vector<std::string> missing;
  if (info.api_version < VK_API_VERSION_1_2) missing.push_back("Vulkan 1.2");
  if (!has_compute) missing.push_back("a compute queue");
  if (!info.push_descriptor) missing.push_back(VK_KHR_PUSH_DESCRIPTOR_EXTENSION_NAME);
  if (!info.timeline_semaphore) missing.push_back("timeline semaphores");
  if (!info.subgroup_arithmetic) missing.push_back("subgroup basic, arithmetic, vote and shuffle operations in compute shaders");
  info.suitable = missing.empty();
  for (size_t i = 0; i < missing.size(); ++i)
    info.unsuitable_reason += (i ? ", " : "lacks ") + missing[i];
  return info;
}

const DeviceInfo& choose_device(const std::vector<DeviceInfo>& devices, const std::string& override_spec) {
  if (devices.empty())
    throw std::runtime_error(
        "no Vulkan device found: install a Vulkan driver (for a CPU-only machine: apt-get install "
        "mesa-vulkan-drivers, which provides lavapipe)");
  std::ostringstream seen;
  for (const auto& d : devices) seen << "\n  [" << d.index << "] " << d.name << " (" << d.type_name() << ")";

  if (!override_spec.empty()) {
    const DeviceInfo* pick = nullptr;
    const bool numeric = std::all_of(override_spec.begin(), override_spec.end(),
                                     [](unsigned char c) { return std::isdigit(c); });
    if (numeric) {
      const unsigned long idx = std::stoul(override_spec);
      for (const auto& d : devices)
        if (d.index == idx) pick = &d;
    } else {
      for (const auto& d : devices)
        if (lower(d.name).find(lower(override_spec)) != std::string::npos) {
          pick = &d;
          break;
        }
    }
    if (!pick) throw std::runtime_error("S4D_DEVICE=" + override_spec + " matches no Vulkan device; devices:" + seen.str());
    if (!pick->suitable)
      throw std::runtime_error("S4D_DEVICE=" + override_spec + " selects '" + pick->name + "', which " +
                               pick->unsuitable_reason);
    return *pick;
  }

  const DeviceInfo* best = nullptr;
  for (const auto& d : devices) {
    if (!d.suitable) continue;
    if (!best || device_type_rank(d.type) > device_type_rank(best->type) ||
        (device_type_rank(d.type) == device_type_rank(best->type) && d.device_local_bytes > best->device_local_bytes))
      best = &d;
  }
  if (!best) {
    std::ostringstream why;
    for (const auto& d : devices) why << "\n  [" << d.index << "] " << d.name << ": " << d.unsuitable_reason;
    throw std::runtime_error("no usable Vulkan device:" + why.str());
  }
  return *best;
}

}  // namespace s4d::engine
