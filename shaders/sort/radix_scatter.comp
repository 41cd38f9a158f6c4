// radix_scatter: stable scatter of one 4-bit digit. One workgroup per block of S4D_RADIX_BLOCK keys,
// processed in S4D_RADIX_ROUNDS rounds of S4D_RADIX_WG keys in order. Within a round each key's rank
// among equal digits comes from one workgroup exclusive scan of packed 8-bit one-hot counters
// (16 bins = one uvec4); the per-digit running base starts at the scanned histogram entry of this
// block and advances by each round's digit counts. Keys are placed by wg_rank(), so stability does
// not depend on how the driver lays out subgroups.
#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_KHR_shader_subgroup_basic : require
#include "s4d_primitives.h"
#include "flat_group.glsl"
#define WG_SIZE S4D_RADIX_WG
#include "wg_scan.glsl"

#if S4D_RADIX_WG > 256 || S4D_RADIX_BINS != 16
#error "packed 8-bit counters need at most 256 invocations and exactly 16 bins"
#endif

layout(local_size_x = S4D_RADIX_WG) in;
layout(push_constant) uniform Push { RadixParams p; };
layout(std430, binding = S4D_B_RADIX_KEYS_IN) readonly buffer KeysIn { uint keys_in[]; };        // [n]
layout(std430, binding = S4D_B_RADIX_VALUES_IN) readonly buffer ValuesIn { uint values_in[]; };  // [n]
layout(std430, binding = S4D_B_RADIX_HIST) readonly buffer Hist { uint hist[]; };  // [16 * num_blocks], scanned
layout(std430, binding = S4D_B_RADIX_KEYS_OUT) writeonly buffer KeysOut { uint keys_out[]; };      // [n]
layout(std430, binding = S4D_B_RADIX_VALUES_OUT) writeonly buffer ValuesOut { uint values_out[]; };  // [n]

shared uint running[S4D_RADIX_BINS];
shared uint round_counts[S4D_RADIX_BINS];

void main() {
  uint g = flat_group_id();
  if (g >= p.num_blocks) return;
  uint rank = wg_rank();
  if (rank < S4D_RADIX_BINS) {
    running[rank] = hist[rank * p.num_blocks + g];
    round_counts[rank] = 0;
  }
  barrier();
  uint base = g * S4D_RADIX_BLOCK;
  for (uint r = 0; r < S4D_RADIX_ROUNDS; ++r) {
    uint round_base = base + r * S4D_RADIX_WG;
    if (round_base >= p.n) break;  // uniform across the workgroup
    uint i = round_base + rank;
    bool valid = i < p.n;
    uint key = valid ? keys_in[i] : 0;
    uint digit = (key >> p.shift) & p.digit_mask;
    uvec4 onehot = uvec4(0);
    if (valid) onehot[digit >> 2] = 1u << (8 * (digit & 3));
    uvec4 total;  // lanes may overflow at 256 equal digits; counts come from round_counts instead
    uvec4 prefix = wg_exclusive_add4(onehot, total);
    if (valid) {
      uint local_rank = (prefix[digit >> 2] >> (8 * (digit & 3))) & 0xffu;
      uint dst = running[digit] + local_rank;
      keys_out[dst] = key;
      values_out[dst] = values_in[i];
      atomicAdd(round_counts[digit], 1u);
    }
    barrier();
    if (rank < S4D_RADIX_BINS) {
      running[rank] += round_counts[rank];
      round_counts[rank] = 0;
    }
    barrier();
  }
}
