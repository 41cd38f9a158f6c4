#include "s4d/engine/context.h"

#include <cstdlib>
#include <cstring>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "s4d/engine/buffer.h"
#include "s4d/engine/check.h"
#include "s4d/engine/pipeline.h"
#include "s4d/engine/recorder.h"
#include "s4d/engine/stage_timer.h"

namespace s4d::engine {

namespace {

constexpr const char* kValidationLayer = "VK_LAYER_KHRONOS_validation";
constexpr size_t kRecentOps = 16;
constexpr size_t kMaxKeptMessages = 64;

bool instance_has_layer(const char* name) {
  uint32_t count = 0;
  S4D_VK_CHECK(vkEnumerateInstanceLayerProperties(&count, nullptr));
  std::vector<VkLayerProperties> layers(count);
  S4D_VK_CHECK(vkEnumerateInstanceLayerProperties(&count, layers.data()));
  layers.resize(count);
  for (const auto& l : layers)
    if (std::strcmp(l.layerName, name) == 0) return true;
  return false;
}

bool device_has_extension(VkPhysicalDevice device, const std::string& name) {
  uint32_t count = 0;
  S4D_VK_CHECK(vkEnumerateDeviceExtensionProperties(device, nullptr, &count, nullptr));
  std::vector<VkExtensionProperties> exts(count);
  S4D_VK_CHECK(vkEnumerateDeviceExtensionProperties(device, nullptr, &count, exts.data()));
  exts.resize(count);
  for (const auto& e : exts)
    if (name == e.extensionName) return true;
  return false;
}

bool instance_has_extension(const char* name) {
  uint32_t count = 0;
  S4D_VK_CHECK(vkEnumerateInstanceExtensionProperties(nullptr, &count, nullptr));
  std::vector<VkExtensionProperties> exts(count);
  S4D_VK_CHECK(vkEnumerateInstanceExtensionProperties(nullptr, &count, exts.data()));
  exts.resize(count);
  for (const auto& e : exts)
    if (std::strcmp(e.extensionName, name) == 0) return true;
  return false;
}

VkInstance create_plain_instance(bool validation, bool debug_utils, const std::vector<std::string>& extra_exts = {}) {
  VkApplicationInfo app{.sType = VK_STRUCTURE_TYPE_APPLICATION_INFO,
                        .pApplicationName = "style4d",
                        .applicationVersion = VK_MAKE_API_VERSION(0, 0, 1, 0),
                        .pEngineName = "s4d",
                        .engineVersion = VK_MAKE_API_VERSION(0, 0, 1, 0),
                        .apiVersion = VK_API_VERSION_1_3};
  std::vector<const char*> layers, exts;
  if (validation) layers.push_back(kValidationLayer);
  if (debug_utils) exts.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
  for (const std::string& e : extra_exts) exts.push_back(e.c_str());
  VkInstanceCreateInfo ci{.sType = VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO,
                          .pApplicationInfo = &app,
                          .enabledLayerCount = static_cast<uint32_t>(layers.size()),
                          .ppEnabledLayerNames = layers.data(),
                          .enabledExtensionCount = static_cast<uint32_t>(exts.size()),
                          .ppEnabledExtensionNames = exts.data()};
  VkInstance instance = VK_NULL_HANDLE;
  VkResult r = vkCreateInstance(&ci, nullptr, &instance);
  if (r == VK_ERROR_INCOMPATIBLE_DRIVER)
    throw std::runtime_error(
        "no Vulkan driver is installed (vkCreateInstance: VK_ERROR_INCOMPATIBLE_DRIVER); on a machine "
        "without a GPU install lavapipe: apt-get install mesa-vulkan-drivers");
  S4D_VK_CHECK_CTX(r, "creating the Vulkan instance");
  return instance;
}

std::vector<DeviceInfo> enumerate(VkInstance instance, std::vector<VkPhysicalDevice>* handles) {
  uint32_t count = 0;
  S4D_VK_CHECK(vkEnumeratePhysicalDevices(instance, &count, nullptr));
  std::vector<VkPhysicalDevice> devices(count);
  S4D_VK_CHECK(vkEnumeratePhysicalDevices(instance, &count, devices.data()));
  std::vector<DeviceInfo> infos;
  for (uint32_t i = 0; i < count; ++i) infos.push_back(query_device_info(devices[i], i));
  if (handles) *handles = devices;
  return infos;
}

}  // namespace

ContextOptions ContextOptions::from_env() {
  ContextOptions o;
  if (const char* v = std::getenv("S4D_VALIDATION")) o.validation = std::strcmp(v, "0") != 0 && *v != 0;
  if (const char* d = std::getenv("S4D_DEVICE")) o.device = d;
  return o;
}

std::vector<DeviceInfo> list_devices() {
  VkInstance instance = create_plain_instance(false, false);
  try {
    auto infos = enumerate(instance, nullptr);
    vkDestroyInstance(instance, nullptr);
    return infos;
  } catch (...) {
    vkDestroyInstance(instance, nullptr);
    throw;
  }
}

Context::Context(const ContextOptions& options)
    : validation_(options.validation), device_spec_(options.device), instance_extensions_(options.instance_extensions),
      device_extensions_(options.device_extensions), can_present_(options.can_present),
      map_device_memory_(options.map_device_memory),
      max_groups_x_(options.max_groups_x) {
  try {
    create_instance();
    create_device();
  } catch (...) {
    if (timeline_) vkDestroySemaphore(device_, timeline_, nullptr);
    if (command_pool_) vkDestroyCommandPool(device_, command_pool_, nullptr);
    if (device_) vkDestroyDevice(device_, nullptr);
    if (messenger_) {
      auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
          vkGetInstanceProcAddr(instance_, "vkDestroyDebugUtilsMessengerEXT"));
      destroy(instance_, messenger_, nullptr);
    }
    if (instance_) vkDestroyInstance(instance_, nullptr);
    throw;
  }
}

void Context::create_instance() {
  if (validation_ && !instance_has_layer(kValidationLayer))
    throw std::runtime_error(std::string("S4D_VALIDATION=1 but ") + kValidationLayer +
                             " is not installed (apt-get install vulkan-validationlayers)");
  for (const std::string& e : instance_extensions_)
    if (!instance_has_extension(e.c_str()))
      throw std::runtime_error("the Vulkan instance lacks the extension " + e +
                               " (needed to show a window; is the driver's window-system support installed?)");
  const bool debug_utils = instance_has_extension(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
  instance_ = create_plain_instance(validation_, debug_utils, instance_extensions_);
  if (debug_utils) {
    set_object_name_ = reinterpret_cast<PFN_vkSetDebugUtilsObjectNameEXT>(
        vkGetInstanceProcAddr(instance_, "vkSetDebugUtilsObjectNameEXT"));
    cmd_begin_label_ = reinterpret_cast<PFN_vkCmdBeginDebugUtilsLabelEXT>(
        vkGetInstanceProcAddr(instance_, "vkCmdBeginDebugUtilsLabelEXT"));
    cmd_end_label_ = reinterpret_cast<PFN_vkCmdEndDebugUtilsLabelEXT>(
        vkGetInstanceProcAddr(instance_, "vkCmdEndDebugUtilsLabelEXT"));
  }
  if (validation_ && debug_utils) {
    auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance_, "vkCreateDebugUtilsMessengerEXT"));
    VkDebugUtilsMessengerCreateInfoEXT ci{
        .sType = VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT,
        .messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT,
        .messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT,
        .pfnUserCallback = &Context::on_debug_message,
        .pUserData = this};
    S4D_VK_CHECK(create(instance_, &ci, nullptr, &messenger_));
  }
}

void Context::create_device() {
  std::vector<VkPhysicalDevice> handles;
  std::vector<DeviceInfo> infos = enumerate(instance_, &handles);
  require_presentation(infos, handles);
  info_ = choose_device(infos, device_spec_);
  physical_ = handles[info_.index];
  vkGetPhysicalDeviceMemoryProperties(physical_, &memory_props_);
  unified_memory_ = map_device_memory_ &&
                    (info_.type == VK_PHYSICAL_DEVICE_TYPE_CPU || info_.type == VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU);

  std::vector<const char*> exts = {VK_KHR_PUSH_DESCRIPTOR_EXTENSION_NAME};
  for (const std::string& e : device_extensions_) exts.push_back(e.c_str());
  VkPhysicalDeviceShaderAtomicFloatFeaturesEXT atomic_float{
      .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SHADER_ATOMIC_FLOAT_FEATURES_EXT,
      .shaderBufferFloat32AtomicAdd = info_.float_atomic_add_buffer,
      .shaderSharedFloat32AtomicAdd = info_.float_atomic_add_shared};
  VkPhysicalDeviceVulkan12Features f12{.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES,
                                       .shaderFloat16 = info_.fp16_arithmetic,
                                       .timelineSemaphore = VK_TRUE};
  if (info_.float_atomic_add_buffer || info_.float_atomic_add_shared) {
    exts.push_back(VK_EXT_SHADER_ATOMIC_FLOAT_EXTENSION_NAME);
    f12.pNext = &atomic_float;
  }
  VkPhysicalDeviceVulkan11Features f11{.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_1_FEATURES,
                                       .pNext = &f12,
                                       .storageBuffer16BitAccess = info_.storage_16bit};
  VkPhysicalDeviceFeatures2 features{.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, .pNext = &f11};
  features.features.shaderInt64 = info_.int64;

  const float priority = 1.0f;
  VkDeviceQueueCreateInfo qci{.sType = VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO,
                              .queueFamilyIndex = info_.compute_queue_family,
                              .queueCount = 1,
                              .pQueuePriorities = &priority};
  VkDeviceCreateInfo dci{.sType = VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO,
                         .pNext = &features,
                         .queueCreateInfoCount = 1,
                         .pQueueCreateInfos = &qci,
                         .enabledExtensionCount = static_cast<uint32_t>(exts.size()),
                         .ppEnabledExtensionNames = exts.data()};
  S4D_VK_CHECK_CTX(vkCreateDevice(physical_, &dci, nullptr, &device_), "creating a device on " + info_.name);
  vkGetDeviceQueue(device_, info_.compute_queue_family, 0, &queue_);
  cmd_push_descriptor_set_ =
      reinterpret_cast<PFN_vkCmdPushDescriptorSetKHR>(vkGetDeviceProcAddr(device_, "vkCmdPushDescriptorSetKHR"));
  if (!cmd_push_descriptor_set_) throw std::runtime_error("vkCmdPushDescriptorSetKHR is missing on " + info_.name);

  VkCommandPoolCreateInfo pci{.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO,
                              .flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT,
                              .queueFamilyIndex = info_.compute_queue_family};
  S4D_VK_CHECK(vkCreateCommandPool(device_, &pci, nullptr, &command_pool_));
  set_name(VK_OBJECT_TYPE_COMMAND_POOL, reinterpret_cast<uint64_t>(command_pool_), "s4d command pool");

  VkSemaphoreTypeCreateInfo tci{.sType = VK_STRUCTURE_TYPE_SEMAPHORE_TYPE_CREATE_INFO,
                                .semaphoreType = VK_SEMAPHORE_TYPE_TIMELINE,
                                .initialValue = 0};
  VkSemaphoreCreateInfo sci{.sType = VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO, .pNext = &tci};
  S4D_VK_CHECK(vkCreateSemaphore(device_, &sci, nullptr, &timeline_));
  set_name(VK_OBJECT_TYPE_SEMAPHORE, reinterpret_cast<uint64_t>(timeline_), "s4d submission timeline");
}

void Context::require_presentation(std::vector<DeviceInfo>& infos, const std::vector<VkPhysicalDevice>& handles) const {
  for (DeviceInfo& info : infos) {
    if (!info.suitable) continue;
    const VkPhysicalDevice device = handles[info.index];
    for (const std::string& e : device_extensions_)
      if (!device_has_extension(device, e)) {
        info.unsuitable_reason += (info.suitable ? "lacks " : ", ") + e;
        info.suitable = false;
      }
    if (!info.suitable || !can_present_) continue;
    uint32_t count = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(device, &count, nullptr);
    std::vector<VkQueueFamilyProperties> families(count);
    vkGetPhysicalDeviceQueueFamilyProperties(device, &count, families.data());
    // Keep the family query_device_info chose (graphics + compute preferred) when it can present.
    if (can_present_(instance_, device, info.compute_queue_family)) continue;
    bool found = false;
    for (uint32_t q = 0; q < count && !found; ++q)
      if ((families[q].queueFlags & VK_QUEUE_COMPUTE_BIT) && can_present_(instance_, device, q)) {
        info.compute_queue_family = q;
        info.timestamp_valid_bits = families[q].timestampValidBits;
        info.timestamps = info.timestamp_valid_bits > 0 && info.timestamp_period_ns > 0;
        found = true;
      }
    if (!found) {
      info.suitable = false;
      info.unsuitable_reason = "cannot present to the window from a compute queue";
    }
  }
}

Context::~Context() {
  if (device_) {
    // A destructor cannot report failure; if the device is lost, teardown proceeds regardless.
    (void)vkDeviceWaitIdle(device_);
    completed_ = submitted_;
    pipelines_.clear();
    collect_retired();
    vkDestroySemaphore(device_, timeline_, nullptr);
    vkDestroyCommandPool(device_, command_pool_, nullptr);
    vkDestroyDevice(device_, nullptr);
  }
  if (messenger_) {
    auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance_, "vkDestroyDebugUtilsMessengerEXT"));
    destroy(instance_, messenger_, nullptr);
  }
  if (instance_) vkDestroyInstance(instance_, nullptr);
}

uint64_t Context::submit(Recorder&& recorder, const SubmitSync& sync) {
  VkCommandBuffer cmd = recorder.finish();
  const uint64_t value = submitted_ + 1;
  // The timeline first; a binary semaphore's value entry is ignored.
  const VkSemaphore signals[2] = {timeline_, sync.signal};
  const uint64_t signal_values[2] = {value, 0};
  const uint32_t signal_count = sync.signal ? 2 : 1;
  VkTimelineSemaphoreSubmitInfo tsi{.sType = VK_STRUCTURE_TYPE_TIMELINE_SEMAPHORE_SUBMIT_INFO,
                                    .signalSemaphoreValueCount = signal_count,
                                    .pSignalSemaphoreValues = signal_values};
  VkSubmitInfo si{.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO,
                  .pNext = &tsi,
                  .waitSemaphoreCount = sync.wait ? 1u : 0u,
                  .pWaitSemaphores = &sync.wait,
                  .pWaitDstStageMask = &sync.wait_stage,
                  .commandBufferCount = 1,
                  .pCommandBuffers = &cmd,
                  .signalSemaphoreCount = signal_count,
                  .pSignalSemaphores = signals};
  VkResult r = vkQueueSubmit(queue_, 1, &si, VK_NULL_HANDLE);
  if (stage_timer_ && r >= 0) stage_timer_->submitted(std::move(recorder.marks_), value);
  if (stage_timer_ && r < 0) stage_timer_->dropped(std::move(recorder.marks_));
  if (r < 0) vkFreeCommandBuffers(device_, command_pool_, 1, &cmd);  // never submitted: free it now
  if (r == VK_ERROR_DEVICE_LOST) device_lost("vkQueueSubmit");
  S4D_VK_CHECK(r);
  submitted_ = value;
  VkDevice device = device_;
  VkCommandPool pool = command_pool_;
  retire([device, pool, cmd] { vkFreeCommandBuffers(device, pool, 1, &cmd); });
  return value;
}

void Context::wait(uint64_t value) {
  if (value > submitted_)
    throw std::logic_error("wait for submission " + std::to_string(value) + ", but only " + std::to_string(submitted_) +
                           " were submitted");
  if (value > completed_) {
    ++host_waits_;
    VkSemaphoreWaitInfo wi{.sType = VK_STRUCTURE_TYPE_SEMAPHORE_WAIT_INFO,
                           .semaphoreCount = 1,
                           .pSemaphores = &timeline_,
                           .pValues = &value};
    VkResult r = vkWaitSemaphores(device_, &wi, UINT64_MAX);
    if (r == VK_ERROR_DEVICE_LOST) device_lost("vkWaitSemaphores");
    S4D_VK_CHECK(r);
    completed_ = value;
  }
  if (stage_timer_) stage_timer_->completed(completed_);
  collect_retired();
}

void Context::wait_idle() { wait(submitted_); }

void Context::retire(std::function<void()> destroy) {
  if (submitted_ <= completed_ && open_recorders_ == 0) {
    destroy();  // nothing in flight or being recorded can use it
    return;
  }
  // A recorder still open may reference the object: keep it until every recorder open now has been
  // submitted (or dropped) and that submission has completed. Not "the next submission": another
  // one (an upload through staging, a second recorder) may come first and complete before.
  retired_.push_back({open_recorders_ > 0 ? kAfterOpenRecorders : submitted_, std::move(destroy)});
}

void Context::collect_retired() {
  // Nothing in flight and no recorder open: what waited for a recorder that was dropped without
  // being submitted can go too (it would otherwise wait for a submission that never comes).
  const bool idle = completed_ >= submitted_ && open_recorders_ == 0;
  // Every recorder is closed: what waited for them waits for the last submission made so far.
  if (open_recorders_ == 0)
    for (Retired& r : retired_)
      if (r.after == kAfterOpenRecorders) r.after = submitted_;
  while (!retired_.empty() && (idle || retired_.front().after <= completed_)) {
    auto destroy = std::move(retired_.front().destroy);
    retired_.pop_front();
    destroy();
  }
}

void Context::device_lost(const char* where) {
  std::ostringstream msg;
  msg << "the Vulkan device '" << info_.name << "' was lost (driver crash, GPU reset or timeout) in " << where
      << "; last recorded operations:";
  for (const auto& op : recent_ops_) msg << " " << op;
  throw VulkanError(VK_ERROR_DEVICE_LOST, msg.str());
}

void Context::note_op(const std::string& name) {
  recent_ops_.push_back(name);
  if (recent_ops_.size() > kRecentOps) recent_ops_.pop_front();
}

void Context::upload(Buffer& dst, const void* data, size_t bytes, size_t dst_offset) {
  if (dst_offset + bytes > dst.size())
    throw std::invalid_argument("upload of " + std::to_string(bytes) + " bytes at offset " + std::to_string(dst_offset) +
                                " overruns buffer '" + dst.name() + "' of " + std::to_string(dst.size()) + " bytes");
  if (bytes == 0) return;
  wait_idle();
  if (dst.mapped()) {
    std::memcpy(static_cast<char*>(dst.mapped()) + dst_offset, data, bytes);
    return;
  }
  Buffer staging(*this, dst.name() + " (upload staging)", bytes, BufferKind::staging);
  std::memcpy(staging.mapped(), data, bytes);
  Recorder rec(*this, "upload " + dst.name());
  rec.copy(staging, dst, bytes, 0, dst_offset);
  run(std::move(rec));
}

void Context::download(const Buffer& src, void* data, size_t bytes, size_t src_offset) {
  if (src_offset + bytes > src.size())
    throw std::invalid_argument("download of " + std::to_string(bytes) + " bytes at offset " + std::to_string(src_offset) +
                                " overruns buffer '" + src.name() + "' of " + std::to_string(src.size()) + " bytes");
  if (bytes == 0) return;
  wait_idle();
  if (src.mapped()) {
    std::memcpy(data, static_cast<const char*>(src.mapped()) + src_offset, bytes);
    return;
  }
  Buffer staging(*this, src.name() + " (readback staging)", bytes, BufferKind::staging);
  Recorder rec(*this, "download " + src.name());
  rec.copy(src, staging, bytes, src_offset, 0);
  run(std::move(rec));
  std::memcpy(data, staging.mapped(), bytes);
}

const Pipeline& Context::pipeline(const std::string& name, std::span<const uint32_t> spirv,
                                  const std::vector<SpecConstant>& spec) {
  auto key = std::make_pair(name, spec);
  auto it = pipelines_.find(key);
  if (it == pipelines_.end())
    it = pipelines_.emplace(std::move(key), std::make_unique<Pipeline>(*this, name, spirv, spec)).first;
  return *it->second;
}

uint32_t Context::memory_type(uint32_t type_bits, VkMemoryPropertyFlags required, VkMemoryPropertyFlags preferred) const {
  int fallback = -1;
  for (uint32_t i = 0; i < memory_props_.memoryTypeCount; ++i) {
    if (!(type_bits & (1u << i))) continue;
    const VkMemoryPropertyFlags f = memory_props_.memoryTypes[i].propertyFlags;
    if ((f & required) != required) continue;
    if ((f & preferred) == preferred) return i;
    if (fallback < 0) fallback = static_cast<int>(i);
  }
  if (fallback < 0) throw std::runtime_error("no Vulkan memory type with the required properties on " + info_.name);
  return static_cast<uint32_t>(fallback);
}

void Context::set_name(VkObjectType type, uint64_t handle, const std::string& name) const {
  if (!set_object_name_ || !handle) return;
  VkDebugUtilsObjectNameInfoEXT ni{.sType = VK_STRUCTURE_TYPE_DEBUG_UTILS_OBJECT_NAME_INFO_EXT,
                                   .objectType = type,
                                   .objectHandle = handle,
                                   .pObjectName = name.c_str()};
  S4D_VK_CHECK(set_object_name_(device_, &ni));
}

uint64_t Context::validation_error_count() const {
  std::lock_guard lock(messages_mutex_);
  return validation_errors_;
}

std::vector<std::string> Context::take_validation_messages() {
  std::lock_guard lock(messages_mutex_);
  return std::exchange(validation_messages_, {});
}

VkBool32 Context::on_debug_message(VkDebugUtilsMessageSeverityFlagBitsEXT severity, VkDebugUtilsMessageTypeFlagsEXT,
                                   const VkDebugUtilsMessengerCallbackDataEXT* data, void* user) {
  auto* self = static_cast<Context*>(user);
  const bool error = severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
  const std::string text = std::string(error ? "validation error: " : "validation warning: ") +
                           (data && data->pMessage ? data->pMessage : "(no message)");
  std::lock_guard lock(self->messages_mutex_);
  if (error) ++self->validation_errors_;
  if (error && self->validation_messages_.size() < kMaxKeptMessages) self->validation_messages_.push_back(text);
  std::cerr << "[s4d] " << text << "\n";
  return VK_FALSE;
}

}  // namespace s4d::engine
