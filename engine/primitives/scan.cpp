// Host side of the exclusive scan: recursion over levels of block sums.
//   level 0: data (n elements), blocks of S4D_SCAN_BLOCK
//   scan_reduce writes one sum per block into the next level (in the scratch buffer), which is
//   scanned the same way, then scan_downsweep scans each block of this level offset by its
//   scanned block sum. A level of one block needs only scan_downsweep.
#include "s4d/primitives/scan.h"

#include <stdexcept>

#include "s4d_primitives.h"
#include "s4d/primitives/shader_pipeline.h"

namespace s4d::primitives {

namespace {

// Each level of block sums starts 256-byte aligned: the largest minStorageBufferOffsetAlignment
// Vulkan allows, so the bound ranges are valid on every device.
constexpr size_t kLevelAlignWords = 64;

size_t aligned_words(uint32_t words) { return (size_t{words} + kLevelAlignWords - 1) / kLevelAlignWords * kLevelAlignWords; }

void scan_level(engine::Recorder& rec, const engine::Buffer& data, size_t data_offset, uint32_t n,
                const engine::Buffer& scratch, size_t scratch_offset) {
  engine::Context& ctx = rec.context();
  const uint32_t blocks = ceil_div(n, S4D_SCAN_BLOCK);
  const gpu::ScanParams params{.n = n, .num_blocks = blocks, ._pad0 = 0, ._pad1 = 0};
  const engine::BufferRange level(data, data_offset, size_t{n} * 4);
  if (blocks == 1) {
    rec.dispatch(shader_pipeline(ctx, shaders::Id::scan_downsweep),
                 {S4D_BIND(SCAN_DATA, level), S4D_BIND(SCAN_PARTIALS, scratch)}, params, 1);
    return;
  }
  const engine::BufferRange partials(scratch, scratch_offset, size_t{blocks} * 4);
  rec.dispatch(shader_pipeline(ctx, shaders::Id::scan_reduce),
               {S4D_BIND(SCAN_DATA, level), S4D_BIND(SCAN_PARTIALS, partials)}, params, blocks);
  rec.barrier();
  scan_level(rec, scratch, scratch_offset, blocks, scratch, scratch_offset + aligned_words(blocks) * 4);
  rec.barrier();
  rec.dispatch(shader_pipeline(ctx, shaders::Id::scan_downsweep),
               {S4D_BIND(SCAN_DATA, level), S4D_BIND(SCAN_PARTIALS, partials)}, params, blocks);
}

}  // namespace

size_t scan_scratch_bytes(uint32_t n) {
  size_t words = 0;
  for (uint32_t level = n; level > S4D_SCAN_BLOCK;) {
    level = ceil_div(level, S4D_SCAN_BLOCK);
    words += aligned_words(level);
  }
  return words * 4;
}

void cmd_exclusive_scan(engine::Recorder& rec, const engine::Buffer& data, uint32_t n, const engine::Buffer& scratch) {
  if (data.size() < size_t{n} * 4)
    throw std::invalid_argument("exclusive scan: buffer '" + data.name() + "' holds fewer than " + std::to_string(n) + " u32");
  if (scratch.size() < scan_scratch_bytes(n))
    throw std::invalid_argument("exclusive scan: scratch buffer '" + scratch.name() + "' has " +
                                std::to_string(scratch.size()) + " bytes, " + std::to_string(scan_scratch_bytes(n)) +
                                " needed for n = " + std::to_string(n));
  if (n == 0) return;
  scan_level(rec, data, 0, n, scratch, 0);
}

}  // namespace s4d::primitives
