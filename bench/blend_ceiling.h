// The device's ceiling for the rasterizer's blend loop (shaders/bench/blend_ceiling.comp): the same
// per-tile loop over a synthetic list in which every (pixel, entry) pair is blended, timed with GPU
// timestamps around the one dispatch.
#pragma once
#include <cstdint>

#include "s4d/engine/context.h"
#include "timing.h"

namespace s4d::bench {

struct CeilingTiming {
  uint32_t width = 0, height = 0, tiles = 0, list_length = 0;
  Timing gpu;                 // GPU timestamps around the dispatch
  uint64_t pixel_pairs = 0;   // tiles * 256 * list_length, all of them blended
  double pairs_per_s = 0;     // pixel_pairs / median time
  bool all_blended = false;   // every image pixel blended every entry: no skip, no early termination
};

// Throws std::invalid_argument when list_length is 0 or above S4D_CEILING_MAX_LIST.
CeilingTiming bench_blend_ceiling(engine::Context& ctx, uint32_t width, uint32_t height, uint32_t list_length,
                                  int repeats, uint32_t seed = 1);

// The list length that matches a rasterizer run: its average tile list rounded up to whole batches
// of 256, within 256..S4D_CEILING_MAX_LIST.
uint32_t ceiling_list_length(uint64_t instances, uint32_t tiles);

}  // namespace s4d::bench
