// scan_reduce: partials[g] = sum of block g of data (S4D_SCAN_BLOCK elements per workgroup).
// First pass of the reduce-then-scan exclusive prefix sum; no inter-workgroup communication, so no
// forward-progress assumption.
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
layout(std430, binding = S4D_B_SCAN_DATA) readonly buffer Data { uint data[]; };      // [n]
layout(std430, binding = S4D_B_SCAN_PARTIALS) writeonly buffer Partials { uint partials[]; };  // [num_blocks]

void main() {
  uint g = flat_group_id();
  if (g >= p.num_blocks) return;
  uint begin = g * S4D_SCAN_BLOCK + gl_LocalInvocationIndex;
  uint sum = 0;
  for (uint k = 0; k < S4D_SCAN_ITEMS; ++k) {
    uint i = begin + k * S4D_SCAN_WG;
    if (i < p.n) sum += data[i];
  }
  uint total;
  wg_exclusive_add(sum, total);
  if (gl_LocalInvocationIndex == 0) partials[g] = total;
}
