// style4d devices: every Vulkan device with the features and limits the engine uses, and which one
// the engine would choose.
#include <nlohmann/json.hpp>

#include <cstdlib>
#include <iostream>

#include "args.h"
#include "commands.h"
#include "device_json.h"
#include "s4d/engine/context.h"

namespace s4d::cli {

namespace {
std::string yes_no(bool b) { return b ? "yes" : "no"; }
}  // namespace

int cmd_devices(const std::vector<std::string>& argv) {
  const std::vector<OptionSpec> specs = {{"json", "print JSON instead of a table", false}};
  Args args(argv, specs);
  if (args.help()) {
    std::cout << usage("devices", "[--json]",
                       "Lists the Vulkan devices, their features (float atomics, fp16, subgroup size) and limits,\n"
                       "and marks with * the one the engine picks (S4D_DEVICE overrides).",
                       specs);
    return 0;
  }
  if (!args.positionals().empty()) throw UsageError("unexpected argument '" + args.positionals().front() + "'");
  const auto devices = engine::list_devices();
  const char* override_spec = std::getenv("S4D_DEVICE");
  int chosen = -1;
  std::string choice_error;
  try {
    chosen = static_cast<int>(engine::choose_device(devices, override_spec ? override_spec : "").index);
  } catch (const std::exception& e) {
    choice_error = e.what();
  }

  if (args.flag("json")) {
    nlohmann::json out = nlohmann::json::array();
    for (const auto& d : devices) {
      nlohmann::json j = device_json(d);
      j["chosen"] = static_cast<int>(d.index) == chosen;
      out.push_back(j);
    }
    std::cout << out.dump(2) << "\n";
    return chosen >= 0 ? 0 : 1;
  }

  for (const auto& d : devices) {
    std::cout << (static_cast<int>(d.index) == chosen ? "* " : "  ") << "[" << d.index << "] " << d.name << "\n"
              << "      type                 " << d.type_name() << "\n"
              << "      Vulkan               " << d.api_version_string() << "\n"
              << "      driver               " << d.driver_name << " (" << d.driver_info << ")\n"
              << "      usable               " << (d.suitable ? "yes" : "no: " + d.unsuitable_reason) << "\n"
              << "      subgroup size        " << d.subgroup_size << " (min " << d.min_subgroup_size << ", max "
              << d.max_subgroup_size << "), arithmetic " << yes_no(d.subgroup_arithmetic) << "\n"
              << "      float atomic add     buffer " << yes_no(d.float_atomic_add_buffer) << ", shared "
              << yes_no(d.float_atomic_add_shared) << "\n"
              << "      fp16 arithmetic      " << yes_no(d.fp16_arithmetic) << ", 16-bit storage "
              << yes_no(d.storage_16bit) << ", int64 " << yes_no(d.int64) << "\n"
              << "      max workgroups       " << d.max_workgroup_count[0] << " x " << d.max_workgroup_count[1] << " x "
              << d.max_workgroup_count[2] << ", " << d.max_workgroup_invocations << " invocations, "
              << d.max_shared_memory_bytes / 1024 << " KiB shared\n"
              << "      max storage buffer   " << (d.max_storage_buffer_range >> 20) << " MiB, allocation "
              << (d.max_memory_allocation_size >> 20) << " MiB, device-local heap " << (d.device_local_bytes >> 20)
              << " MiB\n"
              << "      push constants       " << d.max_push_constant_bytes << " bytes\n"
              << "      timestamps           "
              << (d.timestamps ? "yes (" + std::to_string(d.timestamp_period_ns) + " ns/tick)" : std::string("no"))
              << "\n";
  }
  if (chosen < 0) {
    std::cerr << "style4d devices: error: " << choice_error << "\n";
    return 1;
  }
  return 0;
}

}  // namespace s4d::cli
