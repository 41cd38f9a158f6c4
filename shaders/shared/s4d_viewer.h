// Shared layouts of the viewer's kernels.
#ifndef S4D_VIEWER_H
#define S4D_VIEWER_H
#include "s4d_common.h"

#ifdef __cplusplus
#define S4D_VIEWER_FN inline
#else
#define S4D_VIEWER_FN
#endif

S4D_NAMESPACE_BEGIN

#define S4D_PACK_WG 256

// Binding ids of present_pack.
#define S4D_B_PACK_RGB 0     // [src_height*src_width*3] f32, the rasterizer's image
#define S4D_B_PACK_PIXELS 1  // [height*width] u32, 8-bit pixels in the swapchain's byte order

// Push constants of present_pack. A source smaller than the output (the viewer's lower-resolution
// frames while the view moves) is upsampled bilinearly; an equal size copies pixel for pixel.
struct PackParams {
  uint width;       // of the output pixels
  uint height;
  uint src_width;   // of the rasterizer's image, <= width
  uint src_height;  // <= height
  uint swap_rb;     // 1: bytes B, G, R, A (BGRA swapchains); 0: R, G, B, A
  uint _pad0;
  uint _pad1;
  uint _pad2;
};

// Where output pixel x of `dst` pixels samples a source of `src` pixels, pixel centres aligned:
// s = (x + 0.5) src / dst - 0.5 = ((2x + 1) src - dst) / (2 dst), clamped to [0, src - 1].
// Integer numerator and denominator, so GLSL and C++ find the same pixel `i0` and the same
// weight numerator `num` of `i0 + 1` (weight num / (2 dst)); at src == dst, num is 0 and i0 is x.
struct PackTap {
  uint i0;
  uint num;
};

S4D_VIEWER_FN PackTap pack_tap(uint x, uint src, uint dst) {
  PackTap t;  // member by member: GLSL has no braces here and clang 14 no parenthesized aggregates
  t.i0 = 0u;
  t.num = 0u;
  int n = int((2u * x + 1u) * src) - int(dst);
  if (n <= 0) return t;  // left of pixel 0's centre: pixel 0 alone
  t.i0 = uint(n) / (2u * dst);
  t.num = uint(n) % (2u * dst);
  if (t.i0 >= src - 1u) {  // right of the last pixel's centre: that pixel alone
    t.i0 = src - 1u;
    t.num = 0u;
  }
  return t;
}

S4D_NAMESPACE_END

#endif  // S4D_VIEWER_H
