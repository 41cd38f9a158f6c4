// Host side of the radix sort: per 4-bit pass, radix_count -> exclusive scan of the digit-major
// histogram -> radix_scatter, ping-ponging between the caller's buffers and the temporaries; an
// odd pass count ends with a copy back so the result always lands in the caller's buffers.
#include "s4d/primitives/radix_sort.h"

#include <algorithm>
#include <stdexcept>

#include "s4d/primitives/scan.h"
#include "s4d_primitives.h"
#include "s4d/primitives/shader_pipeline.h"

namespace s4d::primitives {

RadixSortRequirements radix_sort_requirements(uint32_t n) {
  const uint32_t blocks = ceil_div(n, S4D_RADIX_BLOCK);
  const uint32_t hist = blocks * S4D_RADIX_BINS;
  return {.temp_keys_bytes = size_t{n} * 4,
          .temp_values_bytes = size_t{n} * 4,
          .histogram_bytes = size_t{hist} * 4,
          .scan_scratch_bytes = scan_scratch_bytes(hist)};
}

RadixSortScratch::RadixSortScratch(engine::Context& ctx, uint32_t cap, const std::string& name) : capacity(cap) {
  const RadixSortRequirements r = radix_sort_requirements(cap);
  temp_keys = engine::Buffer(ctx, name + " temp keys", r.temp_keys_bytes);
  temp_values = engine::Buffer(ctx, name + " temp values", r.temp_values_bytes);
  histogram = engine::Buffer(ctx, name + " histogram", r.histogram_bytes);
  scan_scratch = engine::Buffer(ctx, name + " scan scratch", r.scan_scratch_bytes);
}

namespace {

// Both forms: n is the count (live == nullptr) or the bound of the live count.
void record_sort(engine::Recorder& rec, const engine::Buffer& keys, const engine::Buffer& values, uint32_t n,
                 const LiveCount* live, uint32_t key_bits, const RadixSortScratch& scratch) {
  if (key_bits == 0 || key_bits > 32)
    throw std::invalid_argument("radix sort: key_bits must be 1..32, got " + std::to_string(key_bits));
  if (n > scratch.capacity)
    throw std::invalid_argument("radix sort: " + std::to_string(n) + " pairs exceed the scratch capacity of " +
                                std::to_string(scratch.capacity));
  if (keys.size() < size_t{n} * 4 || values.size() < size_t{n} * 4)
    throw std::invalid_argument("radix sort: buffers '" + keys.name() + "' / '" + values.name() + "' hold fewer than " +
                                std::to_string(n) + " u32");
  if (n <= 1) return;

  engine::Context& ctx = rec.context();
  const engine::Pipeline& count =
      shader_pipeline(ctx, live ? shaders::Id::radix_count_live : shaders::Id::radix_count);
  const engine::Pipeline& scatter =
      shader_pipeline(ctx, live ? shaders::Id::radix_scatter_live : shaders::Id::radix_scatter);
  const uint32_t blocks = ceil_div(n, S4D_RADIX_BLOCK);
  const uint32_t passes = ceil_div(key_bits, S4D_RADIX_BITS);
  const uint32_t hist_entries = blocks * S4D_RADIX_BINS;

  const engine::Buffer* src_k = &keys;
  const engine::Buffer* src_v = &values;
  const engine::Buffer* dst_k = &scratch.temp_keys;
  const engine::Buffer* dst_v = &scratch.temp_values;
  for (uint32_t pass = 0; pass < passes; ++pass) {
    const uint32_t shift = pass * S4D_RADIX_BITS;
    const uint32_t digit_bits = std::min<uint32_t>(S4D_RADIX_BITS, key_bits - shift);
    const gpu::RadixParams params{.n = n, .shift = shift, .num_blocks = blocks, .digit_mask = (1u << digit_bits) - 1};
    if (live) {  // blocks past the live ones are not run: their histogram entries must read zero
      rec.fill(scratch.histogram, 0, size_t{hist_entries} * 4);
      rec.barrier();
      rec.dispatch_indirect(count,
                            {S4D_BIND(RADIX_COUNT_KEYS, *src_k), S4D_BIND(RADIX_COUNT_HIST, scratch.histogram),
                             S4D_BIND(RADIX_COUNT_LIVE, live->count)},
                            params, live->groups, live->groups_offset);
    } else {
      rec.dispatch(count, {S4D_BIND(RADIX_COUNT_KEYS, *src_k), S4D_BIND(RADIX_COUNT_HIST, scratch.histogram)}, params,
                   blocks);
    }
    rec.barrier();
    cmd_exclusive_scan(rec, scratch.histogram, hist_entries, scratch.scan_scratch);
    rec.barrier();
    if (live)
      rec.dispatch_indirect(
          scatter,
          {S4D_BIND(RADIX_KEYS_IN, *src_k), S4D_BIND(RADIX_VALUES_IN, *src_v), S4D_BIND(RADIX_HIST, scratch.histogram),
           S4D_BIND(RADIX_KEYS_OUT, *dst_k), S4D_BIND(RADIX_VALUES_OUT, *dst_v), S4D_BIND(RADIX_LIVE, live->count)},
          params, live->groups, live->groups_offset);
    else
      rec.dispatch(
          scatter,
          {S4D_BIND(RADIX_KEYS_IN, *src_k), S4D_BIND(RADIX_VALUES_IN, *src_v), S4D_BIND(RADIX_HIST, scratch.histogram),
           S4D_BIND(RADIX_KEYS_OUT, *dst_k), S4D_BIND(RADIX_VALUES_OUT, *dst_v)},
          params, blocks);
    rec.barrier();
    std::swap(src_k, dst_k);
    std::swap(src_v, dst_v);
  }
  if (src_k != &keys) {  // the bound: the live count is not known here
    rec.copy(*src_k, keys, size_t{n} * 4);
    rec.copy(*src_v, values, size_t{n} * 4);
  }
}

}  // namespace

void cmd_radix_sort(engine::Recorder& rec, const engine::Buffer& keys, const engine::Buffer& values, uint32_t n,
                    uint32_t key_bits, const RadixSortScratch& scratch) {
  record_sort(rec, keys, values, n, nullptr, key_bits, scratch);
}

void cmd_radix_sort(engine::Recorder& rec, const engine::Buffer& keys, const engine::Buffer& values,
                    const LiveCount& live, uint32_t key_bits, const RadixSortScratch& scratch) {
  record_sort(rec, keys, values, live.bound, &live, key_bits, scratch);
}

}  // namespace s4d::primitives
