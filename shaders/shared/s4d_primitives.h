// Shared layouts of the generic GPU primitives: exclusive prefix scan, LSD radix sort, iota.
#ifndef S4D_PRIMITIVES_H
#define S4D_PRIMITIVES_H
#include "s4d_common.h"

S4D_NAMESPACE_BEGIN

// One workgroup of the scan kernels handles S4D_SCAN_BLOCK consecutive elements:
// S4D_SCAN_WG threads x S4D_SCAN_ITEMS items each.
#define S4D_SCAN_WG 256
#define S4D_SCAN_ITEMS 4
#define S4D_SCAN_BLOCK (S4D_SCAN_WG * S4D_SCAN_ITEMS)

// Radix sort: 4-bit digits, 8 passes for a 32-bit key. A workgroup ranks a whole block in one
// workgroup scan: each invocation takes S4D_RADIX_ITEMS consecutive keys and counts its digits in
// 16 packed 16-bit counters (two uvec4); the exclusive prefix of a bin is at most
// S4D_RADIX_BLOCK - 1, so S4D_RADIX_BLOCK must stay below 65536.
#define S4D_RADIX_BITS 4
#define S4D_RADIX_BINS 16
#define S4D_RADIX_WG 256
#define S4D_RADIX_ITEMS 8
#define S4D_RADIX_BLOCK (S4D_RADIX_WG * S4D_RADIX_ITEMS)

#define S4D_IOTA_WG 256

// Binding ids.
#define S4D_B_SCAN_DATA 0      // [n] u32, scanned in place
#define S4D_B_SCAN_PARTIALS 1  // [ceil(n / S4D_SCAN_BLOCK)] u32 block sums / their exclusive scan
#define S4D_B_RADIX_COUNT_KEYS 0  // [n] u32 (radix_count)
#define S4D_B_RADIX_COUNT_HIST 1  // [S4D_RADIX_BINS * num_blocks] u32, digit-major (radix_count)
#define S4D_B_RADIX_KEYS_IN 0    // [n] u32
#define S4D_B_RADIX_VALUES_IN 1  // [n] u32
#define S4D_B_RADIX_HIST 2       // [S4D_RADIX_BINS * num_blocks] u32, digit-major
#define S4D_B_RADIX_KEYS_OUT 3   // [n] u32
#define S4D_B_RADIX_VALUES_OUT 4 // [n] u32
#define S4D_B_RADIX_COUNT_LIVE 2 // [1] u32 live key count (radix_count_live)
#define S4D_B_RADIX_LIVE 5       // [1] u32 live key count (radix_scatter_live)
#define S4D_B_IOTA_OUT 0         // [n] u32

// Push constants of scan_reduce, scan_downsweep.
struct ScanParams {
  uint n;           // elements to scan
  uint num_blocks;  // ceil(n / S4D_SCAN_BLOCK); 1 means the block needs no partials
  uint _pad0;
  uint _pad1;
};

// Push constants of radix_count, radix_scatter (and their _live variants, which sort
// min(n, live count) keys but keep the histogram laid out for n).
struct RadixParams {
  uint n;           // keys to sort (_live: their bound)
  uint shift;       // bit offset of this pass's digit
  uint num_blocks;  // ceil(n / S4D_RADIX_BLOCK)
  uint digit_mask;  // bins of this pass minus one: S4D_RADIX_BINS - 1, less on a last partial digit
};

// Push constants of iota: out[i] = first + i.
struct IotaParams {
  uint n;
  uint first;
  uint _pad0;
  uint _pad1;
};

S4D_NAMESPACE_END

#endif  // S4D_PRIMITIVES_H
