// Stable LSD radix sort of (u32 key, u32 value) pairs on the GPU, 4 bits per pass, sorting only the
// low `key_bits` bits (tile ids need few). Reduce-then-scan per pass: per-block digit histograms,
// one exclusive scan, a stable scatter. Vulkan-style: query storage requirements, the caller owns
// the scratch buffers, commands are recorded into the caller's command buffer.
//
// Synchronisation: the caller adds Recorder::barrier() after writing keys/values and before the
// call, and again after the call before reading them. The sorted pairs end in `keys`/`values`.
#pragma once
#include <cstddef>
#include <cstdint>

#include "s4d/engine/buffer.h"
#include "s4d/engine/context.h"
#include "s4d/engine/recorder.h"

namespace s4d::primitives {

struct RadixSortRequirements {
  size_t temp_keys_bytes = 0;
  size_t temp_values_bytes = 0;
  size_t histogram_bytes = 0;
  size_t scan_scratch_bytes = 0;
};

RadixSortRequirements radix_sort_requirements(uint32_t n);

// Scratch buffers sized by radix_sort_requirements for up to `capacity` pairs.
struct RadixSortScratch {
  engine::Buffer temp_keys, temp_values, histogram, scan_scratch;
  uint32_t capacity = 0;
  RadixSortScratch() = default;
  RadixSortScratch(engine::Context& ctx, uint32_t capacity, const std::string& name = "radix sort");
};

// Sorts keys[0..n) with values[0..n) by the low key_bits (1..32) bits of each key; stable.
// Throws std::invalid_argument when n exceeds the scratch capacity or a buffer is too small.
void cmd_radix_sort(engine::Recorder& rec, const engine::Buffer& keys, const engine::Buffer& values, uint32_t n,
                    uint32_t key_bits, const RadixSortScratch& scratch);

// A count that only the device knows: live = min(bound, the u32 at the start of `count`), and the
// workgroups of one pass, ceil(live / S4D_RADIX_BLOCK) split as Recorder::split_groups does, as a
// VkDispatchIndirectCommand in `groups` at `groups_offset`. A kernel writes both before the call.
struct LiveCount {
  const engine::Buffer& count;
  const engine::Buffer& groups;
  size_t groups_offset;
  uint32_t bound;
};

// As above for keys[0..live): buffers and scratch are sized for live.bound, the passes dispatch
// only the live blocks (indirect), and the same pairs come out in the same order as
// cmd_radix_sort(keys, values, live) would give. Entries from live to bound may change.
void cmd_radix_sort(engine::Recorder& rec, const engine::Buffer& keys, const engine::Buffer& values,
                    const LiveCount& live, uint32_t key_bits, const RadixSortScratch& scratch);

}  // namespace s4d::primitives
