// The rasterizer family's inputs and shared-memory batch, common to raster_fwd and raster_bwd in
// both variants: S4D_RASTER_BATCH tile-list entries at a time, loaded cooperatively by the tile's
// 256 invocations. The style variant also stages each entry's 16 style parts (MLP weights, quadric).
// Straight-line code only (llvmpipe's loop cap, see s4d_splat.h). Needs the push-constant block `p`.
#ifndef RASTER_BATCH_GLSL
#define RASTER_BATCH_GLSL
#include "raster_variant.glsl"
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
layout(std430, binding = S4D_B_RASTER_STYLE_MLP) readonly buffer StyleMlp { vec4 mlp[]; };  // [N*13] vec4

shared vec4 s_style[S4D_STYLE_SLOT_PARTS * S4D_STYLE_BATCH];  // slot j's parts at 16 j .. (s4d_style_splat.h)

// An upper bound of Gaussian g's opacity offset dO = sigmoid(z_3) - 0.5 over every depth feature a
// pixel can give it (raster_pair.glsl's pair_bound): interval arithmetic through its MLP, the
// feature's range [0, 1] (ndc), (0, 1) (sigmoid input) or any float (relative). Each interval is
// widened by 1e-6 of the magnitudes that produced it, far more than the float rounding of the pairs'
// own evaluation (a dot of 4 terms: under 4 ulp of the sum of magnitudes) and of exp's error
// through a sigmoid; so o + bound >= o + dO on every pair, and the tile's pairs whose bound skips
// are pairs the MLP would skip too. With a trained or zero-initialised last layer the bound is far
// below the 0.5 of dO's range, which spares the MLP most low-opacity pairs. NaN weights give 0.5.
vec4 style_sigmoid(vec4 a) { return 1.0 / (1.0 + exp(-a)); }

// [lo, hi] -> the interval of W x + b over it, widened (see above). Written out, not a loop
// (llvmpipe's loop cap: this runs once per batch, s4d_style_splat.h).
void style_affine_interval(mat4 W, vec4 b, inout vec4 lo, inout vec4 hi) {
  precise vec4 a0 = W[0] * lo[0], c0 = W[0] * hi[0], a1 = W[1] * lo[1], c1 = W[1] * hi[1];
  precise vec4 a2 = W[2] * lo[2], c2 = W[2] * hi[2], a3 = W[3] * lo[3], c3 = W[3] * hi[3];
  precise vec4 l = b + min(a0, c0) + min(a1, c1) + min(a2, c2) + min(a3, c3);
  precise vec4 h = b + max(a0, c0) + max(a1, c1) + max(a2, c2) + max(a3, c3);
  precise vec4 mag = abs(b) + 1.0 + abs(W[0]) * max(abs(lo[0]), abs(hi[0])) + abs(W[1]) * max(abs(lo[1]), abs(hi[1])) +
                     abs(W[2]) * max(abs(lo[2]), abs(hi[2])) + abs(W[3]) * max(abs(lo[3]), abs(hi[3]));
  lo = l - 1e-6 * mag, hi = h + 1e-6 * mag;
}

float style_opacity_bound(uint g) {
  uint w = uint(S4D_STYLE_MLP_VEC4S) * g;
  bool squash = (p.flags & S4D_STYLE_INPUT_SIGMOID) != 0u;
  precise float x0 = squash ? 1.0 / (1.0 + exp(-p.time)) : p.time;
  float x1_lo = squash ? (p.depth_mode == S4D_STYLE_DEPTH_NDC ? 0.5 : 0.0) : (p.depth_mode == S4D_STYLE_DEPTH_NDC ? 0.0 : -1e30);
  float x1_hi = squash ? (p.depth_mode == S4D_STYLE_DEPTH_NDC ? 0.7310586 : 1.0) : (p.depth_mode == S4D_STYLE_DEPTH_NDC ? 1.0 : 1e30);
  vec4 lo = vec4(x0, x1_lo, 0.0, 0.0), hi = vec4(x0, x1_hi, 0.0, 0.0);
  style_affine_interval(mat4(mlp[w], mlp[w + 1u], vec4(0.0), vec4(0.0)), mlp[w + 2u], lo, hi);
  lo = max(style_sigmoid(lo) - 1e-6, 0.0), hi = min(style_sigmoid(hi) + 1e-6, 1.0);
  style_affine_interval(mat4(mlp[w + 3u], mlp[w + 4u], mlp[w + 5u], mlp[w + 6u]), mlp[w + 7u], lo, hi);
  lo = max(style_sigmoid(lo) - 1e-6, 0.0), hi = min(style_sigmoid(hi) + 1e-6, 1.0);
  style_affine_interval(mat4(mlp[w + 8u], mlp[w + 9u], mlp[w + 10u], mlp[w + 11u]), mlp[w + 12u], lo, hi);
  precise float bound = style_sigmoid(hi).w + 1e-6 - 0.5;
  return bound < 0.5 ? bound : 0.5;
}

// One style part (k = 16 slot + part) of the batch: an MLP vec4, or a quadric vec4 with the
// opacity-offset bound in the last one.
void style_load_part(uint k, uint first, bool backward, uint count) {
  if (k >= uint(S4D_STYLE_SLOT_PARTS) * count) return;
  uint j = k / uint(S4D_STYLE_SLOT_PARTS), part = k - uint(S4D_STYLE_SLOT_PARTS) * j;
  uint g = gaussian_ids[raster_slot_instance(first, backward, j)];
  if (part < uint(S4D_STYLE_SLOT_QUADRIC)) s_style[k] = mlp[S4D_STYLE_MLP_VEC4S * g + part];
  else if (part < uint(S4D_STYLE_SLOT_PARTS) - 1u) s_style[k] = quadric[3u * g + part - uint(S4D_STYLE_SLOT_QUADRIC)];
  else s_style[k] = vec4(quadric[3u * g + 2u].x, style_opacity_bound(g), 0.0, 0.0);
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
