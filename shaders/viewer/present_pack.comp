// present_pack: the rasterizer's float RGB image to 8-bit pixels that a copy puts straight into a
// swapchain image (or a screenshot). One thread per output pixel. Reads rgb [src_height*src_width*3]
// f32, writes pixels [height*width] u32 whose bytes in memory are R, G, B, 255 (or B, G, R, 255 when
// p.swap_rb is 1). A smaller source (the viewer's frames while the view moves) is upsampled
// bilinearly with pixel centres aligned (pack_tap in s4d_viewer.h): at 1/2 to 1/4 scale nearest
// would show blocks of 2-4 pixels that crawl as the camera moves, bilinear costs four reads per
// pixel, which is nothing next to the rasterizer. A tap of weight 0 is never read, so an equal size
// copies pixel for pixel and the output is the unscaled pack's, bit for bit.
// Quantisation is io::write_png's: NaN -> 0, clamp to [0, 1], level = floor(v * 255 + 0.5), so a
// capture equals the offline renderer's PNG of the same image. Twin: viewer/include/s4d/viewer/present_pack_ref.h.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "s4d_viewer.h"
#include "flat_group.glsl"

layout(local_size_x = S4D_PACK_WG) in;
layout(push_constant) uniform Push { PackParams p; };
layout(std430, binding = S4D_B_PACK_RGB) readonly buffer Rgb { float rgb[]; };        // [SH*SW*3] f32
layout(std430, binding = S4D_B_PACK_PIXELS) writeonly buffer Pixels { uint pixels[]; };  // [H*W] u32

uint level(float v) {
  if (isnan(v)) return 0u;
  return uint(floor(clamp(v, 0.0, 1.0) * 255.0 + 0.5));
}

vec3 texel(uint x, uint y) {
  uint i = 3u * (y * p.src_width + x);
  return vec3(rgb[i], rgb[i + 1u], rgb[i + 2u]);
}

// Along x at row y: the tap's pixel, or its blend with the next one.
vec3 row_sample(PackTap tx, uint y) {
  vec3 a = texel(tx.i0, y);
  if (tx.num == 0u) return a;
  return mix(a, texel(tx.i0 + 1u, y), float(tx.num) / float(2u * p.width));
}

void main() {
  uint i = flat_group_id() * S4D_PACK_WG + gl_LocalInvocationIndex;
  if (i >= p.width * p.height) return;
  PackTap tx = pack_tap(i % p.width, p.src_width, p.width);
  PackTap ty = pack_tap(i / p.width, p.src_height, p.height);
  vec3 c = row_sample(tx, ty.i0);
  if (ty.num != 0u) c = mix(c, row_sample(tx, ty.i0 + 1u), float(ty.num) / float(2u * p.height));
  uint r = level(c.r), g = level(c.g), b = level(c.b);
  if (p.swap_rb != 0u) {
    uint t = r;
    r = b;
    b = t;
  }
  pixels[i] = r | (g << 8) | (b << 16) | (255u << 24);
}
