// style_raster_fwd: raster_fwd with each Gaussian's style MLP evaluated per (pixel, Gaussian) pair
// inside the blend loop (ALGORITHMS.md 4.3): the pair blends colour c_i + dRGB with alpha
// min(0.99, (o_i + dO) G). One 16x16 workgroup per tile, one invocation per pixel; the tile's
// depth-sorted list streams through shared memory in batches of S4D_STYLE_BATCH (style_batch.glsl),
// and the workgroup stops once every pixel's transmittance would drop below 1e-4. Outputs as
// raster_fwd, so raster_bwd's inputs and project_bwd work unchanged.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "s4d_style_splat.h"
#include "flat_group.glsl"
#if S4D_STYLE_UNROLL != 4
#error "main() calls blend() four times per iteration"
#endif

layout(local_size_x = S4D_TILE_SIZE, local_size_y = S4D_TILE_SIZE) in;
layout(push_constant) uniform Push { StyleRasterParams p; };
#include "style_batch.glsl"
#include "style_sample.glsl"
layout(std430, binding = S4D_B_SRAST_RGB) writeonly buffer OutRgb { float out_rgb[]; };
layout(std430, binding = S4D_B_SRAST_ALPHA) writeonly buffer OutAlpha { float out_alpha[]; };
layout(std430, binding = S4D_B_SRAST_DEPTH) writeonly buffer OutDepth { float out_depth[]; };
layout(std430, binding = S4D_B_SRAST_COUNT) writeonly buffer OutCount { uint out_count[]; };
layout(std430, binding = S4D_B_SRAST_LAST) writeonly buffer OutLast { uint out_last[]; };
layout(std430, binding = S4D_B_SRAST_FINAL_T) writeonly buffer OutFinalT { float out_final_t[]; };

shared uint s_done;

bool done;
float T = 1.0, depth = 0.0;
vec3 color = vec3(0.0);
uint count = 0u, last = 0u;

// Blends slot j of the batch whose first slot is list position `position0`.
void blend(uint j, uint batch, uint position0) {
  if (done || j >= batch) return;
  StyleSample s = style_sample(j);
  if (s.b.skip) return;
  float next = T * (1.0 - s.b.alpha);
  if (next < S4D_MIN_TRANSMITTANCE) {
    done = true;  // this Gaussian is not added, as in graphdeco
    return;
  }
  vec4 cd = s_color_depth[j];
  color += (cd.rgb + s.drgb) * (s.b.alpha * T);
  depth += cd.w * (s.b.alpha * T);
  T = next;
  ++count;
  last = position0 + j + 1u;
}

void main() {
  uint tile = flat_group_id();
  if (tile >= p.size.z * p.size.w) return;  // whole workgroups only: the barriers below stay uniform
  uint lid = gl_LocalInvocationIndex;
  uvec2 pix = uvec2(tile % p.size.z, tile / p.size.z) * S4D_TILE_SIZE + gl_LocalInvocationID.xy;
  bool inside = pix.x < p.size.x && pix.y < p.size.y;
  centre = vec2(pix) + 0.5;
  ray = (centre - p.intrinsics.zw) / p.intrinsics.xy;
  uvec2 range = ranges[tile];
  done = !inside;

  for (uint base = range.x; base < range.y; base += S4D_STYLE_BATCH) {
    barrier();
    if (lid == 0u) s_done = 0u;
    barrier();
    if (done) atomicAdd(s_done, 1u);
    barrier();
    if (s_done == S4D_TILE_PIXELS) break;
    uint batch = min(uint(S4D_STYLE_BATCH), range.y - base);
    style_load_batch(lid, base, false, batch);
    barrier();
    uint position0 = base - range.x;
    // S4D_STYLE_UNROLL entries per iteration, written out (llvmpipe's loop cap, s4d_style_splat.h).
    for (uint j = 0u; !done && j < batch; j += S4D_STYLE_UNROLL) {
      blend(j, batch, position0), blend(j + 1u, batch, position0);
      blend(j + 2u, batch, position0), blend(j + 3u, batch, position0);
    }
  }
  if (!inside) return;
  uint o = pix.y * p.size.x + pix.x;
  vec3 rgb = color + T * p.background.rgb;
  out_rgb[3u * o] = rgb.r, out_rgb[3u * o + 1u] = rgb.g, out_rgb[3u * o + 2u] = rgb.b;
  out_alpha[o] = 1.0 - T;
  out_depth[o] = depth;
  out_count[o] = count;
  out_last[o] = last;
  out_final_t[o] = T;
}
