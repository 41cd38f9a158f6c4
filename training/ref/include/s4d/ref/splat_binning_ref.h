// CPU twins of the rasterizer's binning kernels (shaders/splat/count_tiles, emit_instances,
// tile_ranges, tile_list_stats), one function per kernel on the kernels' own buffer layouts. Chained
// with an exclusive scan and a stable sort by tile they give ref::tile_lists (splat_raster_ref.h).
#pragma once
#include <algorithm>
#include <cstdint>
#include <vector>

namespace s4d::ref {

struct CountTiles {
  std::vector<uint32_t> offsets;  // [n + 1]: tiles_touched in depth order, then 0 (scanned afterwards)
  uint32_t instances_low = 0;     // sum of tiles_touched mod 2^32
  uint32_t carries = 0;           // how often that sum wrapped
  uint32_t largest = 0;           // largest tiles_touched
};

inline CountTiles count_tiles(const std::vector<uint32_t>& sorted_ids, const std::vector<uint32_t>& tiles_touched) {
  CountTiles c;
  c.offsets.resize(sorted_ids.size() + 1, 0);
  uint64_t total = 0;
  for (size_t k = 0; k < sorted_ids.size(); ++k) {
    const uint32_t area = tiles_touched[sorted_ids[k]];
    c.offsets[k] = area;
    total += area;
    c.largest = std::max(c.largest, area);
  }
  c.instances_low = static_cast<uint32_t>(total);
  c.carries = static_cast<uint32_t>(total >> 32);
  return c;
}

struct Instances {
  std::vector<uint32_t> tile_keys, gaussian_ids;
};

// `offsets` is the exclusive scan of count_tiles' output; `info` is project_fwd's uvec4 per
// Gaussian (x_min | y_min << 16, x_max | y_max << 16, radius, clamp bits), max exclusive.
inline Instances emit_instances(const std::vector<uint32_t>& sorted_ids, const std::vector<uint32_t>& offsets,
                                const std::vector<uint32_t>& info, uint32_t tiles_x) {
  Instances out;
  out.tile_keys.resize(offsets.back()), out.gaussian_ids.resize(offsets.back());
  for (size_t k = 0; k < sorted_ids.size(); ++k) {
    const uint32_t g = sorted_ids[k], lo = info[4 * g], hi = info[4 * g + 1];
    uint32_t at = offsets[k];
    for (uint32_t ty = lo >> 16; ty < (hi >> 16); ++ty)
      for (uint32_t tx = lo & 0xFFFFu; tx < (hi & 0xFFFFu); ++tx) out.tile_keys[at] = ty * tiles_x + tx, out.gaussian_ids[at++] = g;
  }
  return out;
}

// (begin, end) per tile over instances sorted by tile; empty tiles keep (0, 0).
inline std::vector<uint32_t> tile_ranges(const std::vector<uint32_t>& sorted_keys, uint32_t tiles) {
  std::vector<uint32_t> ranges(2 * size_t{tiles}, 0);
  for (size_t i = 0; i < sorted_keys.size(); ++i) {
    const uint32_t t = sorted_keys[i];
    if (i == 0 || sorted_keys[i - 1] != t) ranges[2 * t] = static_cast<uint32_t>(i);
    if (i + 1 == sorted_keys.size() || sorted_keys[i + 1] != t) ranges[2 * t + 1] = static_cast<uint32_t>(i + 1);
  }
  return ranges;
}

inline uint32_t longest_tile_list(const std::vector<uint32_t>& ranges) {
  uint32_t longest = 0;
  for (size_t t = 0; 2 * t < ranges.size(); ++t) longest = std::max(longest, ranges[2 * t + 1] - ranges[2 * t]);
  return longest;
}

}  // namespace s4d::ref
