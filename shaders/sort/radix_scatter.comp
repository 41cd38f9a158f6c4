// radix_scatter: stable scatter of one digit. One workgroup per block of S4D_RADIX_BLOCK keys;
// invocation r (by wg_rank(), see wg_scan.glsl) owns keys [r * ITEMS, r * ITEMS + ITEMS) of the
// block, counts their digits in 16 packed 16-bit counters, and one workgroup exclusive scan of
// those counters gives, per digit, how many equal digits precede its keys in the block. A key's
// destination is the scanned histogram entry of (digit, block) + that prefix + the equal digits
// among the invocation's own earlier keys: stable by construction, whatever the subgroup layout.
#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_KHR_shader_subgroup_basic : require
#include "s4d_primitives.h"
#include "flat_group.glsl"
#define WG_SIZE S4D_RADIX_WG
#include "wg_scan.glsl"

#if S4D_RADIX_BLOCK >= 65536 || S4D_RADIX_BINS != 16
#error "16-bit packed counters need fewer than 65536 keys per block and exactly 16 bins"
#endif

layout(local_size_x = S4D_RADIX_WG) in;
layout(push_constant) uniform Push { RadixParams p; };
layout(std430, binding = S4D_B_RADIX_KEYS_IN) readonly buffer KeysIn { uint keys_in[]; };        // [n]
layout(std430, binding = S4D_B_RADIX_VALUES_IN) readonly buffer ValuesIn { uint values_in[]; };  // [n]
layout(std430, binding = S4D_B_RADIX_HIST) readonly buffer Hist { uint hist[]; };  // [16 * num_blocks], scanned
layout(std430, binding = S4D_B_RADIX_KEYS_OUT) writeonly buffer KeysOut { uint keys_out[]; };      // [n]
layout(std430, binding = S4D_B_RADIX_VALUES_OUT) writeonly buffer ValuesOut { uint values_out[]; };  // [n]
#if S4D_RADIX_LIVE
layout(std430, binding = S4D_B_RADIX_LIVE) readonly buffer Live { uint live[]; };  // the live count
#endif

shared uint block_base[S4D_RADIX_BINS];

// Packed counter of digit d: bins 0..7 live in `lo`, 8..15 in `hi`, two 16-bit lanes per u32.
uint packed_get(uvec4 lo, uvec4 hi, uint d) {
  uint word = d < 8 ? lo[(d >> 1) & 3] : hi[(d >> 1) & 3];
  return (word >> (16 * (d & 1))) & 0xffffu;
}

void main() {
  uint g = flat_group_id();
  if (g >= p.num_blocks) return;
#if S4D_RADIX_LIVE
  uint n = min(p.n, live[0]);
#else
  uint n = p.n;
#endif
  uint rank = wg_rank();
  if (rank < S4D_RADIX_BINS) block_base[rank] = hist[rank * p.num_blocks + g];

  uint first = g * S4D_RADIX_BLOCK + rank * S4D_RADIX_ITEMS;
  uint keys[S4D_RADIX_ITEMS];
  uvec4 lo = uvec4(0), hi = uvec4(0);
  for (uint k = 0; k < S4D_RADIX_ITEMS; ++k) {
    uint i = first + k;
    keys[k] = i < n ? keys_in[i] : 0;
    if (i < n) {
      uint d = (keys[k] >> p.shift) & p.digit_mask;
      uint inc = 1u << (16 * (d & 1));
      if (d < 8) lo[(d >> 1) & 3] += inc; else hi[(d >> 1) & 3] += inc;
    }
  }
  uvec4 total_lo, total_hi;  // unused: block totals come from the histogram
  wg_exclusive_add8(lo, hi, total_lo, total_hi);  // also orders block_base's writes before the reads below

  for (uint k = 0; k < S4D_RADIX_ITEMS; ++k) {
    uint i = first + k;
    if (i >= n) break;
    uint d = (keys[k] >> p.shift) & p.digit_mask;
    uint earlier = 0;  // equal digits among this invocation's own earlier keys
    for (uint j = 0; j < k; ++j) earlier += ((keys[j] >> p.shift) & p.digit_mask) == d ? 1u : 0u;
    uint dst = block_base[d] + packed_get(lo, hi, d) + earlier;
    keys_out[dst] = keys[k];
    values_out[dst] = values_in[i];
  }
}
