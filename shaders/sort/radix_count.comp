// radix_count: per-block histogram of one 4-bit digit, written digit-major
// (hist[d * num_blocks + g]) so that one exclusive scan of hist yields every block's scatter base.
// One workgroup per block of S4D_RADIX_BLOCK keys; counting order is irrelevant, so shared atomics.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "s4d_primitives.h"
#include "flat_group.glsl"

layout(local_size_x = S4D_RADIX_WG) in;
layout(push_constant) uniform Push { RadixParams p; };
layout(std430, binding = S4D_B_RADIX_COUNT_KEYS) readonly buffer KeysIn { uint keys_in[]; };  // [n]
layout(std430, binding = S4D_B_RADIX_COUNT_HIST) writeonly buffer Hist { uint hist[]; };  // [16 * num_blocks]
#if S4D_RADIX_LIVE
// The live count; blocks past it are not dispatched (indirect) and keep the zeros the host filled in.
layout(std430, binding = S4D_B_RADIX_COUNT_LIVE) readonly buffer Live { uint live[]; };
#endif

shared uint counts[S4D_RADIX_BINS];

void main() {
  uint g = flat_group_id();
  if (g >= p.num_blocks) return;
#if S4D_RADIX_LIVE
  uint n = min(p.n, live[0]);
#else
  uint n = p.n;
#endif
  uint lid = gl_LocalInvocationIndex;
  if (lid < S4D_RADIX_BINS) counts[lid] = 0;
  barrier();
  uint base = g * S4D_RADIX_BLOCK;
  for (uint k = lid; k < S4D_RADIX_BLOCK; k += S4D_RADIX_WG) {
    uint i = base + k;
    if (i < n) atomicAdd(counts[(keys_in[i] >> p.shift) & p.digit_mask], 1u);
  }
  barrier();
  if (lid < S4D_RADIX_BINS) hist[lid * p.num_blocks + g] = counts[lid];
}
