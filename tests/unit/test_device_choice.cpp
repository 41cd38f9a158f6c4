// Device choice: discrete > integrated > virtual > CPU; S4D_DEVICE by index or name; unsuitable
// devices are skipped with reasons, and an override to one is refused with the reason.
#include <doctest/doctest.h>

#include <stdexcept>
#include <vector>

#include "s4d/engine/device_info.h"

using s4d::engine::DeviceInfo;

namespace {
DeviceInfo device(uint32_t index, const char* name, VkPhysicalDeviceType type, bool suitable = true) {
  DeviceInfo d;
  d.index = index;
  d.name = name;
  d.type = type;
  d.suitable = suitable;
  if (!suitable) d.unsuitable_reason = "lacks VK_KHR_push_descriptor";
  return d;
}
}  // namespace

TEST_CASE("the best suitable device type wins") {
  std::vector<DeviceInfo> devs = {device(0, "llvmpipe (LLVM 15.0.6, 256 bits)", VK_PHYSICAL_DEVICE_TYPE_CPU),
                                  device(1, "Intel UHD 630", VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU),
                                  device(2, "NVIDIA H100", VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU)};
  CHECK(s4d::engine::choose_device(devs, "").index == 2);
  devs[2].suitable = false;
  CHECK(s4d::engine::choose_device(devs, "").index == 1);
}

TEST_CASE("S4D_DEVICE selects by index or by case-insensitive name") {
  std::vector<DeviceInfo> devs = {device(0, "llvmpipe (LLVM 15.0.6, 256 bits)", VK_PHYSICAL_DEVICE_TYPE_CPU),
                                  device(1, "NVIDIA H100", VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU)};
  CHECK(s4d::engine::choose_device(devs, "0").index == 0);
  CHECK(s4d::engine::choose_device(devs, "LLVMPIPE").index == 0);
  CHECK(s4d::engine::choose_device(devs, "h100").index == 1);
  CHECK_THROWS_WITH_AS(s4d::engine::choose_device(devs, "radeon"), doctest::Contains("matches no Vulkan device"),
                       std::runtime_error);
  CHECK_THROWS_WITH_AS(s4d::engine::choose_device(devs, "7"), doctest::Contains("llvmpipe"), std::runtime_error);
}

TEST_CASE("unsuitable devices are explained") {
  std::vector<DeviceInfo> devs = {device(0, "Old GPU", VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU, false)};
  CHECK_THROWS_WITH_AS(s4d::engine::choose_device(devs, ""), doctest::Contains("push_descriptor"), std::runtime_error);
  CHECK_THROWS_WITH_AS(s4d::engine::choose_device(devs, "0"), doctest::Contains("Old GPU"), std::runtime_error);
  CHECK_THROWS_WITH_AS(s4d::engine::choose_device({}, ""), doctest::Contains("mesa-vulkan-drivers"), std::runtime_error);
}
