// tile_ranges: over the instances sorted by tile id, each invocation marks where its tile's run
// begins and ends, over the live count that instance_args wrote (at most p.n, the
// capacity). Tiles with no instances keep the (0, 0) the host filled in.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "s4d_splat.h"
#include "flat_group.glsl"

layout(local_size_x = S4D_SPLAT_WG) in;
layout(push_constant) uniform Push { BinningParams p; };
layout(std430, binding = S4D_B_RANGES_TILE_KEYS) readonly buffer TileKeys { uint tile_keys[]; };
layout(std430, binding = S4D_B_RANGES_OUT) buffer Ranges { uvec2 ranges[]; };
layout(std430, binding = S4D_B_RANGES_LIVE) readonly buffer Live { uint live; };  // InstanceArgs::live

void main() {
  uint i = flat_group_id() * S4D_SPLAT_WG + gl_LocalInvocationIndex;
  uint n = min(p.n, live);
  if (i >= n) return;
  uint tile = tile_keys[i];
  if (i == 0u || tile_keys[i - 1u] != tile) ranges[tile].x = i;
  if (i + 1u == n || tile_keys[i + 1u] != tile) ranges[tile].y = i + 1u;
}
