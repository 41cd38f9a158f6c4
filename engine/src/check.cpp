#include "s4d/engine/check.h"

#include <sstream>

namespace s4d::engine {

const char* result_name(VkResult result) {
  switch (result) {
#define S4D_CASE(x) \
  case x:           \
    return #x;
    S4D_CASE(VK_SUCCESS)
    S4D_CASE(VK_NOT_READY)
    S4D_CASE(VK_TIMEOUT)
    S4D_CASE(VK_INCOMPLETE)
    S4D_CASE(VK_ERROR_OUT_OF_HOST_MEMORY)
    S4D_CASE(VK_ERROR_OUT_OF_DEVICE_MEMORY)
    S4D_CASE(VK_ERROR_INITIALIZATION_FAILED)
    S4D_CASE(VK_ERROR_DEVICE_LOST)
    S4D_CASE(VK_ERROR_MEMORY_MAP_FAILED)
    S4D_CASE(VK_ERROR_LAYER_NOT_PRESENT)
    S4D_CASE(VK_ERROR_EXTENSION_NOT_PRESENT)
    S4D_CASE(VK_ERROR_FEATURE_NOT_PRESENT)
    S4D_CASE(VK_ERROR_INCOMPATIBLE_DRIVER)
    S4D_CASE(VK_ERROR_TOO_MANY_OBJECTS)
    S4D_CASE(VK_ERROR_FORMAT_NOT_SUPPORTED)
    S4D_CASE(VK_ERROR_FRAGMENTED_POOL)
    S4D_CASE(VK_ERROR_OUT_OF_POOL_MEMORY)
    S4D_CASE(VK_ERROR_INVALID_SHADER_NV)
    S4D_CASE(VK_ERROR_SURFACE_LOST_KHR)
    S4D_CASE(VK_ERROR_OUT_OF_DATE_KHR)
    S4D_CASE(VK_SUBOPTIMAL_KHR)
#undef S4D_CASE
    default:
      return "VK_ERROR_(unknown)";
  }
}

void throw_vk_error(VkResult result, const char* expr, const char* file, int line,
                    const std::string& context) {
  std::ostringstream msg;
  switch (result) {
    case VK_ERROR_OUT_OF_DEVICE_MEMORY:
      msg << "out of device memory";
      break;
    case VK_ERROR_OUT_OF_HOST_MEMORY:
      msg << "out of host memory";
      break;
    case VK_ERROR_DEVICE_LOST:
      msg << "the Vulkan device was lost (driver crash, GPU reset or timeout)";
      break;
    default:
      msg << "Vulkan call failed";
  }
  if (!context.empty()) msg << " (" << context << ")";
  msg << ": " << expr << " returned " << result_name(result) << " at " << file << ":" << line;
  throw VulkanError(result, msg.str());
}

}  // namespace s4d::engine
