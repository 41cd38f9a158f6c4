// emit_instances: one invocation per Gaussian in depth order writes a (tile id, Gaussian id) pair
// for every tile of its rectangle at its scanned offset. Instances therefore leave this kernel in
// depth order, and the stable sort by tile id that follows keeps that order within each tile.
// Instances at or past p.capacity are dropped: the host sees the count exceed it after the frame,
// grows the buffers and renders the frame again.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "s4d_splat.h"
#include "flat_group.glsl"

layout(local_size_x = S4D_SPLAT_WG) in;
layout(push_constant) uniform Push { BinningParams p; };
layout(std430, binding = S4D_B_EMIT_SORTED_IDS) readonly buffer SortedIds { uint sorted_ids[]; };
layout(std430, binding = S4D_B_EMIT_OFFSETS) readonly buffer Offsets { uint offsets[]; };
layout(std430, binding = S4D_B_EMIT_INFO) readonly buffer Info { uvec4 info[]; };
layout(std430, binding = S4D_B_EMIT_TILE_KEYS) writeonly buffer TileKeys { uint tile_keys[]; };
layout(std430, binding = S4D_B_EMIT_GAUSSIAN_IDS) writeonly buffer GaussianIds { uint gaussian_ids[]; };

void main() {
  uint k = flat_group_id() * S4D_SPLAT_WG + gl_LocalInvocationIndex;
  if (k >= p.n) return;
  uint g = sorted_ids[k];
  uvec4 inf = info[g];
  uint x0 = inf.x & 0xFFFFu, y0 = inf.x >> 16, x1 = inf.y & 0xFFFFu, y1 = inf.y >> 16;
  uint out_i = offsets[k];
  for (uint ty = y0; ty < y1; ++ty)
    for (uint tx = x0; tx < x1; ++tx) {
      if (out_i >= p.capacity) return;
      tile_keys[out_i] = ty * p.tiles_x + tx;
      gaussian_ids[out_i] = g;
      ++out_i;
    }
}
