// Error types and the one checking macro every Vulkan call goes through.
#pragma once
#include <vulkan/vulkan.h>

#include <stdexcept>
#include <string>

namespace s4d::engine {

// A Vulkan call returned an error. what() names the call, the VkResult, and the source location.
class VulkanError : public std::runtime_error {
 public:
  VulkanError(VkResult result, const std::string& message)
      : std::runtime_error(message), result_(result) {}
  VkResult result() const { return result_; }

 private:
  VkResult result_;
};

// Human-readable name of a VkResult ("VK_ERROR_DEVICE_LOST").
const char* result_name(VkResult result);

// Builds the message for a failed call and throws VulkanError. `context` adds what was being done
// (a buffer's name, a pipeline's name) when the caller knows it.
[[noreturn]] void throw_vk_error(VkResult result, const char* expr, const char* file, int line,
                                 const std::string& context = {});

}  // namespace s4d::engine

#define S4D_VK_CHECK(expr)                                                        \
  do {                                                                            \
    VkResult s4d_vk_result_ = (expr);                                             \
    if (s4d_vk_result_ < 0)                                                       \
      ::s4d::engine::throw_vk_error(s4d_vk_result_, #expr, __FILE__, __LINE__);   \
  } while (0)

#define S4D_VK_CHECK_CTX(expr, context)                                                   \
  do {                                                                                    \
    VkResult s4d_vk_result_ = (expr);                                                     \
    if (s4d_vk_result_ < 0)                                                               \
      ::s4d::engine::throw_vk_error(s4d_vk_result_, #expr, __FILE__, __LINE__, (context)); \
  } while (0)
