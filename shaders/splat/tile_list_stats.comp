// tile_list_stats: the longest tile list, so the host can refuse what a device cannot blend
// correctly (see S4D_LLVMPIPE_MAX_TILE_LIST) and benchmarks can report it.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "s4d_splat.h"
#include "flat_group.glsl"

layout(local_size_x = S4D_SPLAT_WG) in;
layout(push_constant) uniform Push { BinningParams p; };  // n: tiles
layout(std430, binding = S4D_B_LIST_STATS_RANGES) readonly buffer Ranges { uvec2 ranges[]; };
layout(std430, binding = S4D_B_LIST_STATS_OUT) buffer Stats { uint longest; };

void main() {
  uint t = flat_group_id() * S4D_SPLAT_WG + gl_LocalInvocationIndex;
  if (t >= p.n) return;
  uvec2 r = ranges[t];
  if (r.y > r.x) atomicMax(longest, r.y - r.x);
}
