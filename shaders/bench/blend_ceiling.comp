// blend_ceiling: the device's ceiling for raster_fwd's blend loop. One 16x16 workgroup per tile, one
// invocation per pixel, as in raster_fwd: every tile streams a list of L entries through shared
// memory in batches of 256, votes on "every pixel done" before each batch, and blends with the
// same blend_batch() (splat_blend.glsl). Unlike raster_fwd it reads contiguous arrays (no
// per-Gaussian index gather), every tile blends the same cache-resident list (means are
// tile-local), and the entries' alphas (1/255 < alpha < 0.0045 over a tile) never end a pixel
// early, so all tiles x 256 x L (pixel, entry) pairs are blended.
// Reads xy [L] vec2, conic_opacity [L] vec4, color_depth [L] vec4; writes rgb [H*W*3] and state
// [H*W] uvec4, which keeps depth, count and last live as raster_fwd's outputs do.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "s4d_splat.h"
#include "s4d_bench.h"
#include "flat_group.glsl"

layout(local_size_x = S4D_TILE_SIZE, local_size_y = S4D_TILE_SIZE) in;
layout(push_constant) uniform Push { BlendCeilingParams p; };
layout(std430, binding = S4D_B_CEIL_XY) readonly buffer Xy { vec2 xy[]; };
layout(std430, binding = S4D_B_CEIL_CONIC_OPACITY) readonly buffer ConicOpacity { vec4 conic_opacity[]; };
layout(std430, binding = S4D_B_CEIL_COLOR_DEPTH) readonly buffer ColorDepth { vec4 color_depth[]; };
layout(std430, binding = S4D_B_CEIL_RGB) writeonly buffer OutRgb { float out_rgb[]; };
layout(std430, binding = S4D_B_CEIL_STATE) writeonly buffer OutState { uvec4 out_state[]; };

shared vec2 s_xy[S4D_TILE_PIXELS];
shared vec4 s_conic_opacity[S4D_TILE_PIXELS];
shared vec4 s_color_depth[S4D_TILE_PIXELS];
shared uint s_done;
#include "splat_blend.glsl"

void main() {
  uint tile = flat_group_id();
  if (tile >= p.size.z * p.size.w) return;  // whole workgroups only: the barriers below stay uniform
  uint lid = gl_LocalInvocationIndex;
  uvec2 pix = uvec2(tile % p.size.z, tile / p.size.z) * S4D_TILE_SIZE + gl_LocalInvocationID.xy;
  bool inside = pix.x < p.size.x && pix.y < p.size.y;
  centre = vec2(gl_LocalInvocationID.xy) + 0.5;
  done = !inside;

  for (uint base = 0u; base < p.list_length; base += S4D_TILE_PIXELS) {
    barrier();
    if (lid == 0u) s_done = 0u;
    barrier();
    if (done) atomicAdd(s_done, 1u);
    barrier();
    if (s_done == S4D_TILE_PIXELS) break;
    if (base + lid < p.list_length) {
      s_xy[lid] = xy[base + lid];
      s_conic_opacity[lid] = conic_opacity[base + lid];
      s_color_depth[lid] = color_depth[base + lid];
    }
    barrier();
    blend_batch(min(uint(S4D_TILE_PIXELS), p.list_length - base), base);
  }
  if (!inside) return;
  uint o = pix.y * p.size.x + pix.x;
  vec3 rgb = color + T * p.background.rgb;
  out_rgb[3u * o] = rgb.r, out_rgb[3u * o + 1u] = rgb.g, out_rgb[3u * o + 2u] = rgb.b;
  out_state[o] = uvec4(floatBitsToUint(T), floatBitsToUint(depth), count, last);
}
