// count_tiles: gathers tiles_touched into depth order, offsets[k] = tiles_touched[sorted_ids[k]],
// and writes offsets[n] = 0 so that an exclusive scan of n + 1 entries leaves the instance count
// in offsets[n]. Also counts the instances with carries and the largest rectangle, so the host
// can refuse what the u32 offsets or lavapipe's loop cap (emit_instances) cannot handle.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "s4d_splat.h"
#include "flat_group.glsl"

layout(local_size_x = S4D_SPLAT_WG) in;
layout(push_constant) uniform Push { BinningParams p; };
layout(std430, binding = S4D_B_COUNT_SORTED_IDS) readonly buffer SortedIds { uint sorted_ids[]; };
layout(std430, binding = S4D_B_COUNT_TILES_TOUCHED) readonly buffer TilesTouched { uint tiles_touched[]; };
layout(std430, binding = S4D_B_COUNT_OFFSETS) writeonly buffer Offsets { uint offsets[]; };
layout(std430, binding = S4D_B_COUNT_TOTALS) buffer Totals { uint totals[3]; };

void main() {
  uint k = flat_group_id() * S4D_SPLAT_WG + gl_LocalInvocationIndex;
  if (k < p.n) {
    uint area = tiles_touched[sorted_ids[k]];
    offsets[k] = area;
    if (area == 0u) return;
    // The u32 scan wraps past 2^32 instances; the carries tell the host it did.
    uint before = atomicAdd(totals[0], area);
    if (before + area < before) atomicAdd(totals[1], 1u);
    atomicMax(totals[2], area);
  } else if (k == p.n) {
    offsets[k] = 0u;
  }
}
