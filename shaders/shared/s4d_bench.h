// Shared layouts of the benchmark-only kernels in shaders/bench.
#ifndef S4D_BENCH_H
#define S4D_BENCH_H
#include "s4d_common.h"

// blend_ceiling: the longest list whose entries can all blend without ending a pixel early. Each
// alpha must be >= 1/255 (else the entry is skipped) and (1 - alpha)^L must stay >= 1e-4, so
// L < ln(1e4) / -ln(1 - 1/255) = 2344.
#define S4D_CEILING_MAX_LIST 2048u

#define S4D_B_CEIL_XY 0             // [L] vec2 mean, tile-local pixels (every tile blends the same list)
#define S4D_B_CEIL_CONIC_OPACITY 1  // [L] vec4 (A, B, C, opacity)
#define S4D_B_CEIL_COLOR_DEPTH 2    // [L] vec4 (r, g, b, depth)
#define S4D_B_CEIL_RGB 3            // [H*W*3] blended colour + T_final * background
#define S4D_B_CEIL_STATE 4          // [H*W] uvec4 (T_final bits, depth bits, entries blended, last position)

S4D_NAMESPACE_BEGIN

// Push constants of blend_ceiling.
struct BlendCeilingParams {
  uvec4 size;        // (width, height, tiles_x, tiles_y)
  vec4 background;   // (r, g, b, unused)
  uint list_length;  // L: entries every tile blends, <= S4D_CEILING_MAX_LIST
  uint _pad0;
  uint _pad1;
  uint _pad2;
};

S4D_NAMESPACE_END

#endif  // S4D_BENCH_H
