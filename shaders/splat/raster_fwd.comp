// raster_fwd: one 16x16 workgroup per tile; an invocation blends S4D_RFWD_PIXELS pixels of a column
// (8 on CPU devices, 1 on GPUs: s4d_splat.h). The tile's depth-sorted list
// streams through shared memory in batches of S4D_RASTER_BATCH (raster_batch.glsl); each pixel
// blends front to back until its transmittance would drop below 1e-4 (ALGORITHMS.md 1.5), and the
// workgroup stops as soon as every pixel is done. The style variant (S4D_STYLE=1) runs each pair's
// MLP inside the blend (raster_pair.glsl) and blends c + dRGB with alpha min(0.99, (o + dO) G)
// (ALGORITHMS.md 4.3); its outputs are the plain ones, so raster_bwd and project_bwd read them alike.
#version 450
#extension GL_GOOGLE_include_directive : require
#if S4D_STYLE
#extension GL_KHR_shader_subgroup_arithmetic : require  // raster_walk.glsl
#endif
#include "s4d_style_splat.h"
#include "flat_group.glsl"

layout(local_size_x = S4D_TILE_SIZE, local_size_y = S4D_TILE_SIZE / S4D_RFWD_PIXELS) in;  // S4D_RFWD_INVOCATIONS
layout(push_constant) uniform Push { RasterParams p; };
#include "raster_batch.glsl"
layout(std430, binding = S4D_B_RASTER_RGB) writeonly buffer OutRgb { float out_rgb[]; };
layout(std430, binding = S4D_B_RASTER_ALPHA) writeonly buffer OutAlpha { float out_alpha[]; };
layout(std430, binding = S4D_B_RASTER_DEPTH) writeonly buffer OutDepth { float out_depth[]; };
layout(std430, binding = S4D_B_RASTER_COUNT) writeonly buffer OutCount { uint out_count[]; };
layout(std430, binding = S4D_B_RASTER_LAST) writeonly buffer OutLast { uint out_last[]; };
layout(std430, binding = S4D_B_RASTER_FINAL_T) writeonly buffer OutFinalT { float out_final_t[]; };

shared uint s_done;
#include "splat_blend.glsl"

// Pixel k of the invocation's column.
uvec2 rfwd_pixel(uvec2 origin, uint k) {
  return origin + uvec2(gl_LocalInvocationID.x, S4D_RFWD_PIXELS * gl_LocalInvocationID.y + k);
}

bool rfwd_inside(uvec2 pix) { return pix.x < p.size.x && pix.y < p.size.y; }

// Writes the pixel in the blend globals (splat_blend.glsl) if it lies in the image.
void rfwd_write(uvec2 pix) {
  if (!rfwd_inside(pix)) return;
  uint o = pix.y * p.size.x + pix.x;
  vec3 rgb = color + T * p.background.rgb;
  out_rgb[3u * o] = rgb.r, out_rgb[3u * o + 1u] = rgb.g, out_rgb[3u * o + 2u] = rgb.b;
  out_alpha[o] = 1.0 - T;
  out_depth[o] = depth;
  out_count[o] = count;
  out_last[o] = last;
  out_final_t[o] = T;
}

void main() {
  uint tile = flat_group_id();
  if (tile >= p.size.z * p.size.w) return;  // whole workgroups only: the barriers below stay uniform
  uint lid = gl_LocalInvocationIndex;
  uvec2 origin = uvec2(tile % p.size.z, tile / p.size.z) * S4D_TILE_SIZE;
#if S4D_STYLE
#define RFWD_RAY ray = (centre - p.intrinsics.zw) / p.intrinsics.xy;
#else
#define RFWD_RAY
#endif
#define RFWD_START(k) centre = vec2(rfwd_pixel(origin, k)) + 0.5; RFWD_RAY done = !rfwd_inside(rfwd_pixel(origin, k)); \
  T = 1.0, depth = 0.0, color = vec3(0.0), count = 0u, last = 0u; RFWD_START_OUT(k)
#if S4D_RFWD_PIXELS == 1
#define RFWD_START_OUT(k)
#else
#define RFWD_START_OUT(k) rfwd_px[k].centre = centre, rfwd_px[k].ray = RFWD_START_RAY; RFWD_OUT(k)
#if S4D_STYLE
#define RFWD_START_RAY ray
#else
#define RFWD_START_RAY vec2(0.0)
#endif
#endif
  RFWD_EACH(RFWD_START)
  uvec2 range = ranges[tile];

  for (uint base = range.x; base < range.y; base += S4D_RASTER_BATCH) {
    barrier();
    if (lid == 0u) s_done = 0u;
    barrier();
    if (invocation_done()) atomicAdd(s_done, 1u);
    barrier();
    if (s_done == S4D_RFWD_INVOCATIONS) break;
    uint batch = min(uint(S4D_RASTER_BATCH), range.y - base);
    const uint wg = uint(S4D_RFWD_INVOCATIONS);
#define RFWD_LOAD(k) raster_load_batch(lid + k * wg, base, false, batch);
    RFWD_EACH(RFWD_LOAD)
    barrier();
    blend_batch(batch, base - range.x);
  }
#define RFWD_WRITE(k) RFWD_IN(k) rfwd_write(rfwd_pixel(origin, k));
  RFWD_EACH(RFWD_WRITE)
}
