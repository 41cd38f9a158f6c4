// instance_args: one invocation turns the scanned instance count into the live count and the
// indirect dispatches of the tile sort and tile_ranges (InstanceArgs), split into 2-D rows past
// the device's 1-D limit exactly as Recorder::split_groups splits a host dispatch.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "s4d_splat.h"
#include "s4d_primitives.h"

layout(local_size_x = 1) in;
layout(push_constant) uniform Push { InstanceArgsParams p; };
layout(std430, binding = S4D_B_ARGS_OFFSETS) readonly buffer Offsets { uint offsets[]; };
layout(std430, binding = S4D_B_ARGS_OUT) writeonly buffer Out { InstanceArgs args; };

// Recorder::split_groups on the device: (groups, 1, 1), or y rows of ceil(groups / y).
uvec4 split(uint groups) {
  if (groups <= p.max_groups_x) return uvec4(groups, 1u, 1u, 0u);
  uint y = (groups + p.max_groups_x - 1u) / p.max_groups_x;
  return uvec4((groups + y - 1u) / y, y, 1u, 0u);
}

void main() {
  uint live = min(offsets[p.n], p.capacity);
  args.live = live;
  args._pad0 = 0u;
  args._pad1 = 0u;
  args._pad2 = 0u;
  args.ranges_groups = split((live + S4D_SPLAT_WG - 1u) / S4D_SPLAT_WG);
  args.sort_groups = split((live + S4D_RADIX_BLOCK - 1u) / S4D_RADIX_BLOCK);
}
