// The style variant's compacted walk over a loaded batch. Where the pair's full sample is expensive
// (the MLP), each subgroup first marks the slots that may meet one of its pixels (the cheap bound of
// raster_pair.glsl), then visits only those, in list order. On llvmpipe, whose ifs are masks and
// not branches, this is what keeps the MLP off the pairs no pixel of the subgroup meets: a loop's
// trip count is the only work a subgroup can skip. The unmarked slots are the ones every pixel of
// the subgroup skips, so the results are those of the full walk. `todo` holds one bit per slot and
// is the same in every invocation of the subgroup. Needs GL_KHR_shader_subgroup_arithmetic.
#ifndef RASTER_WALK_GLSL
#define RASTER_WALK_GLSL
#include "raster_variant.glsl"
#if S4D_RASTER_BATCH > 64
#error "the walk keeps one bit per batch slot in a uvec2"
#endif

// Marks slot j in this invocation's bits when it needs the slot. Plain bit operations: one
// subgroupOr per batch (raster_walk_todo) instead of a vote per slot, which llvmpipe runs as a loop
// over the lanes.
void raster_walk_mark(inout uvec2 bits, uint j, bool needed) {
  if (needed) bits[j >> 5u] |= 1u << (j & 31u);
}

// The slots any invocation of the subgroup marked: the same in the whole subgroup.
uvec2 raster_walk_todo(uvec2 bits) { return subgroupOr(bits); }

// The first marked slot, unmarked. `todo` must not be empty.
uint raster_walk_pop(inout uvec2 todo) {
  uint word = todo.x != 0u ? 0u : 1u;
  uint j = 32u * word + uint(findLSB(todo[word]));
  todo[word] &= todo[word] - 1u;
  return j;
}

#endif  // RASTER_WALK_GLSL
