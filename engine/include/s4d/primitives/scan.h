// Exclusive prefix sum of u32 on the GPU (reduce-then-scan; no forward-progress assumption between
// workgroups, no fixed subgroup size). Vulkan-style: query scratch size, record into the caller's
// command buffer.
//
// Synchronisation: the caller makes `data` visible to compute-shader reads before the call
// (Recorder::barrier() after whatever wrote it) and adds Recorder::barrier() after it before
// reading the result. Wraps modulo 2^32 like any u32 sum.
#pragma once
#include <cstddef>
#include <cstdint>

#include "s4d/engine/buffer.h"
#include "s4d/engine/recorder.h"

namespace s4d::primitives {

// Bytes of scratch cmd_exclusive_scan needs for n elements (may be 0; any buffer then works).
size_t scan_scratch_bytes(uint32_t n);

// data[0..n) <- exclusive prefix sums of data[0..n), in place.
void cmd_exclusive_scan(engine::Recorder& rec, const engine::Buffer& data, uint32_t n, const engine::Buffer& scratch);

}  // namespace s4d::primitives
