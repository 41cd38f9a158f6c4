// DeviceInfo as JSON, shared by `devices --json`, the demo report and the benchmarks.
#pragma once
#include <nlohmann/json.hpp>

#include "s4d/engine/device_info.h"

namespace s4d::cli {

inline nlohmann::json device_json(const engine::DeviceInfo& d) {
  return {{"index", d.index},
          {"name", d.name},
          {"type", d.type_name()},
          {"api_version", d.api_version_string()},
          {"driver", d.driver_name},
          {"driver_info", d.driver_info},
          {"usable", d.suitable},
          {"unusable_reason", d.unsuitable_reason},
          {"subgroup_size", d.subgroup_size},
          {"min_subgroup_size", d.min_subgroup_size},
          {"max_subgroup_size", d.max_subgroup_size},
          {"float_atomic_add_buffer", d.float_atomic_add_buffer},
          {"float_atomic_add_shared", d.float_atomic_add_shared},
          {"fp16_arithmetic", d.fp16_arithmetic},
          {"storage_16bit", d.storage_16bit},
          {"int64", d.int64},
          {"max_workgroup_count", {d.max_workgroup_count[0], d.max_workgroup_count[1], d.max_workgroup_count[2]}},
          {"max_workgroup_invocations", d.max_workgroup_invocations},
          {"max_shared_memory_bytes", d.max_shared_memory_bytes},
          {"max_push_constant_bytes", d.max_push_constant_bytes},
          {"max_storage_buffer_range", d.max_storage_buffer_range},
          {"max_memory_allocation_size", d.max_memory_allocation_size},
          {"timestamps", d.timestamps},
          {"timestamp_period_ns", d.timestamp_period_ns}};
}

}  // namespace s4d::cli
