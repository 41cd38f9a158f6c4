// scan_downsweep: exclusive prefix sum of block g of data, in place, offset by partials[g] (the
// already exclusive-scanned block sums; unused when num_blocks == 1). Each invocation takes
// S4D_SCAN_ITEMS consecutive elements at its wg_rank() position.
#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_KHR_shader_subgroup_basic : require
#include "s4d_primitives.h"
#include "flat_group.glsl"
#define WG_SIZE S4D_SCAN_WG
#include "wg_scan.glsl"

layout(local_size_x = S4D_SCAN_WG) in;
layout(push_constant) uniform Push { ScanParams p; };
layout(std430, binding = S4D_B_SCAN_DATA) buffer Data { uint data[]; };                // [n]
layout(std430, binding = S4D_B_SCAN_PARTIALS) readonly buffer Partials { uint partials[]; };  // [num_blocks]

void main() {
  uint g = flat_group_id();
  if (g >= p.num_blocks) return;
  uint rank = wg_rank();
  uint first = g * S4D_SCAN_BLOCK + rank * S4D_SCAN_ITEMS;
  uint items[S4D_SCAN_ITEMS];
  uint sum = 0;
  for (uint k = 0; k < S4D_SCAN_ITEMS; ++k) {
    uint i = first + k;
    items[k] = i < p.n ? data[i] : 0;
    sum += items[k];
  }
  uint total;
  uint running = wg_exclusive_add(sum, total) + (p.num_blocks > 1 ? partials[g] : 0);
  for (uint k = 0; k < S4D_SCAN_ITEMS; ++k) {
    uint i = first + k;
    if (i < p.n) data[i] = running;
    running += items[k];
  }
}
