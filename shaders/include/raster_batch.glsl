// The rasterizer family's inputs and shared-memory batch, common to raster_fwd and raster_bwd in
// both variants: S4D_RASTER_BATCH tile-list entries at a time, loaded cooperatively by the tile's
// 256 invocations. The style variant also stages each entry's 16 style parts (MLP weights, quadric);
// with S4D_STYLE_MLP_HALF=1 (the style_raster_fwd*_half variants, the render side's half storage) it
// reads the weights as packed halves (half_storage.glsl) and stages them as floats.
// Straight-line code only (llvmpipe's loop cap, see s4d_splat.h). Needs the push-constant block `p`.
#ifndef RASTER_BATCH_GLSL
#define RASTER_BATCH_GLSL
#include "raster_variant.glsl"
#include "half_storage.glsl"
#ifndef S4D_STYLE_MLP_HALF
#define S4D_STYLE_MLP_HALF 0
#endif
#if S4D_STYLE_MLP_HALF && !S4D_STYLE
#error "S4D_STYLE_MLP_HALF needs the style variant"
#endif
#if S4D_RASTER_BATCH > S4D_TILE_PIXELS || S4D_STYLE_BATCH * S4D_STYLE_SLOT_PARTS > 4 * S4D_TILE_PIXELS
#error "raster_load_batch() loads one entry's scalars per invocation and the style parts in 4 rounds"
#endif

layout(std430, binding = S4D_B_RASTER_RANGES) readonly buffer Ranges { uvec2 ranges[]; };
layout(std430, binding = S4D_B_RASTER_GAUSSIAN_IDS) readonly buffer GaussianIds { uint gaussian_ids[]; };
layout(std430, binding = S4D_B_RASTER_XY) readonly buffer Xy { vec2 xy[]; };
layout(std430, binding = S4D_B_RASTER_CONIC_OPACITY) readonly buffer ConicOpacity { vec4 conic_opacity[]; };
layout(std430, binding = S4D_B_RASTER_COLOR_DEPTH) readonly buffer ColorDepth { vec4 color_depth[]; };

shared uint s_id[S4D_RASTER_BATCH];
shared vec2 s_xy[S4D_RASTER_BATCH];
shared vec4 s_conic_opacity[S4D_RASTER_BATCH];
shared vec4 s_color_depth[S4D_RASTER_BATCH];

// Instance index of batch slot j: first + j walking forward, first - j walking backward.
uint raster_slot_instance(uint first, bool backward, uint j) { return backward ? first - j : first + j; }

#if S4D_STYLE
layout(std430, binding = S4D_B_RASTER_QUADRIC) readonly buffer Quadric { vec4 quadric[]; };  // [N*3] vec4
#if S4D_STYLE_MLP_HALF
layout(std430, binding = S4D_B_RASTER_STYLE_MLP) readonly buffer StyleMlp { uvec2 mlp_words[]; };  // [N*13] f16 x4
vec4 mlp_vec4(uint v) { return half_vec4(mlp_words[v]); }
#else
layout(std430, binding = S4D_B_RASTER_STYLE_MLP) readonly buffer StyleMlp { vec4 mlp[]; };  // [N*13] vec4
vec4 mlp_vec4(uint v) { return mlp[v]; }
#endif

shared vec4 s_style[S4D_STYLE_SLOT_PARTS * S4D_STYLE_BATCH];  // slot j's parts at 16 j .. (s4d_style_splat.h)

// One style part (k = 16 slot + part) of the batch: an MLP vec4 or a quadric vec4.
void style_load_part(uint k, uint first, bool backward, uint count) {
  if (k >= uint(S4D_STYLE_SLOT_PARTS) * count) return;
  uint j = k / uint(S4D_STYLE_SLOT_PARTS), part = k - uint(S4D_STYLE_SLOT_PARTS) * j;
  uint g = gaussian_ids[raster_slot_instance(first, backward, j)];
  if (part < uint(S4D_STYLE_SLOT_QUADRIC)) s_style[k] = mlp_vec4(S4D_STYLE_MLP_VEC4S * g + part);
  else s_style[k] = quadric[3u * g + part - uint(S4D_STYLE_SLOT_QUADRIC)];
}
#endif

// Loads `count` entries into slots 0..count-1; the caller brackets it with barriers.
void raster_load_batch(uint lid, uint first, bool backward, uint count) {
  if (lid < count) {
    uint g = gaussian_ids[raster_slot_instance(first, backward, lid)];
    s_id[lid] = g;
    s_xy[lid] = xy[g];
    s_conic_opacity[lid] = conic_opacity[g];
    s_color_depth[lid] = color_depth[g];
  }
#if S4D_STYLE
  style_load_part(lid, first, backward, count);
  style_load_part(lid + uint(S4D_TILE_PIXELS), first, backward, count);
  style_load_part(lid + 2u * uint(S4D_TILE_PIXELS), first, backward, count);
  style_load_part(lid + 3u * uint(S4D_TILE_PIXELS), first, backward, count);
#endif
}

#endif  // RASTER_BATCH_GLSL
