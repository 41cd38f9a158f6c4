// present_pack: the rasterizer's float RGB image to 8-bit pixels that a copy puts straight into a
// swapchain image (or a screenshot). One thread per pixel. Reads rgb [H*W*3] f32, writes pixels
// [H*W] u32 whose bytes in memory are R, G, B, 255 (or B, G, R, 255 when p.swap_rb is 1).
// Quantisation is io::write_png's: NaN -> 0, clamp to [0, 1], level = floor(v * 255 + 0.5), so a
// capture equals the offline renderer's PNG of the same image.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "s4d_viewer.h"
#include "flat_group.glsl"

layout(local_size_x = S4D_PACK_WG) in;
layout(push_constant) uniform Push { PackParams p; };
layout(std430, binding = S4D_B_PACK_RGB) readonly buffer Rgb { float rgb[]; };        // [H*W*3] f32
layout(std430, binding = S4D_B_PACK_PIXELS) writeonly buffer Pixels { uint pixels[]; };  // [H*W] u32

uint level(float v) {
  if (isnan(v)) return 0u;
  return uint(floor(clamp(v, 0.0, 1.0) * 255.0 + 0.5));
}

void main() {
  uint i = flat_group_id() * S4D_PACK_WG + gl_LocalInvocationIndex;
  if (i >= p.pixels) return;
  uint r = level(rgb[3 * i]), g = level(rgb[3 * i + 1]), b = level(rgb[3 * i + 2]);
  if (p.swap_rb != 0u) {
    uint t = r;
    r = b;
    b = t;
  }
  pixels[i] = r | (g << 8) | (b << 16) | (255u << 24);
}
