// densify_map: one thread per source Gaussian writes the slot words of its outputs at its scanned
// offset (source index | kind << 30; kinds in s4d_densify.h), so outputs keep source order: the
// original (or child 0) first, then the copy (or child 1). Also tallies clones, splits and pruned
// entries for the host's DensifyResult.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "s4d_densify.h"
#include "flat_group.glsl"

layout(local_size_x = S4D_DENSIFY_WG) in;
layout(push_constant) uniform Push { SlotParams p; };  // n = source Gaussians
layout(std430, binding = S4D_B_MAP_FLAGS) readonly buffer Flags { uint flags[]; };      // [N]
layout(std430, binding = S4D_B_MAP_OFFSETS) readonly buffer Offsets { uint offsets[]; };  // [N + 1]
layout(std430, binding = S4D_B_MAP_SLOTS) writeonly buffer Slots { uint slots[]; };     // [M]
layout(std430, binding = S4D_B_MAP_TALLY) buffer Tally { uint tally[]; };

void main() {
  uint i = flat_group_id() * S4D_DENSIFY_WG + gl_LocalInvocationIndex;
  if (i >= p.n) return;
  uint f = flags[i];
  uint base = offsets[i];
  uint outputs = densify_output_count(f);
  for (uint k = 0u; k < outputs; ++k) slots[base + k] = i | (densify_slot_kind(f, k) << S4D_DENSIFY_SLOT_SHIFT);
  uint grow = f & S4D_DENSIFY_GROW_MASK;
  if (grow == S4D_DENSIFY_CLONE) atomicAdd(tally[S4D_DENSIFY_TALLY_CLONED], 1u);
  if (grow == S4D_DENSIFY_SPLIT) atomicAdd(tally[S4D_DENSIFY_TALLY_SPLIT], 1u);
  uint pruned = densify_pruned_count(f);
  if (pruned > 0u) atomicAdd(tally[S4D_DENSIFY_TALLY_PRUNED], pruned);
}
