// densify_demote: enforce the growth budget. One thread per position j of the candidates sorted by
// ascending mean gradient (stable, so ties keep source order): the source at j is demoted to a plain
// kept-or-pruned Gaussian when it saves outputs and the outputs saved by the candidates before it
// (exclusive prefix) are still short of the excess. Every thread then rewrites its source's output
// count, so the counts can be scanned again; thread 0 zeroes counts[N].
#version 450
#extension GL_GOOGLE_include_directive : require
#include "s4d_densify.h"
#include "flat_group.glsl"

layout(local_size_x = S4D_DENSIFY_WG) in;
layout(push_constant) uniform Push { DemoteParams p; };
layout(std430, binding = S4D_B_DEMOTE_VALUES) readonly buffer Values { uint values[]; };        // [N] sorted sources
layout(std430, binding = S4D_B_DEMOTE_PREFIX) readonly buffer Prefix { uint prefix[]; };        // [N]
layout(std430, binding = S4D_B_DEMOTE_REDUCTION) readonly buffer Reduction { uint reduction[]; };  // [N] by source
layout(std430, binding = S4D_B_DEMOTE_FLAGS) buffer Flags { uint flags[]; };                     // [N] by source
layout(std430, binding = S4D_B_DEMOTE_COUNTS) writeonly buffer Counts { uint counts[]; };        // [N + 1] by source
layout(std430, binding = S4D_B_DEMOTE_TALLY) buffer Tally { uint tally[]; };

void main() {
  uint j = flat_group_id() * S4D_DENSIFY_WG + gl_LocalInvocationIndex;
  if (j == 0u) counts[p.n] = 0u;
  if (j >= p.n) return;
  uint src = values[j];
  uint f = flags[src];
  if (reduction[src] > 0u && prefix[j] < p.excess) {
    f &= ~S4D_DENSIFY_GROW_MASK;
    flags[src] = f;
    atomicAdd(tally[S4D_DENSIFY_TALLY_DEMOTED], 1u);
  }
  counts[src] = densify_output_count(f);
}
