// Shared layouts of the viewer's kernels.
#ifndef S4D_VIEWER_H
#define S4D_VIEWER_H
#include "s4d_common.h"

S4D_NAMESPACE_BEGIN

#define S4D_PACK_WG 256

// Binding ids of present_pack.
#define S4D_B_PACK_RGB 0     // [H*W*3] f32, the rasterizer's image
#define S4D_B_PACK_PIXELS 1  // [H*W] u32, 8-bit pixels in the swapchain's byte order

// Push constants of present_pack.
struct PackParams {
  uint pixels;   // H * W
  uint swap_rb;  // 1: bytes B, G, R, A (BGRA swapchains); 0: R, G, B, A
  uint _pad0;
  uint _pad1;
};

S4D_NAMESPACE_END

#endif  // S4D_VIEWER_H
