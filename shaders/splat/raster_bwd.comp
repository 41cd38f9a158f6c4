// raster_bwd: same tiling as raster_fwd. Each pixel walks its tile's list back to front from its
// last contributor, recovering T_i = T_{i+1} / (1 - alpha_i) from the stored final transmittance
// (ALGORITHMS.md 1.6). The workgroup loads the list in batches up to the tile's last contributor;
// each subgroup starts at its own last contributor (subgroupMax), and every invocation of a
// subgroup visits the same list position at the same step. Where no pixel of the subgroup meets the
// Gaussian, the gradient code is skipped (a uniform branch); otherwise the per-Gaussian cotangents
// are summed over the subgroup and one lane adds them to global memory: with float atomics when the
// device has them (S4D_FLOAT_ATOMICS=1), else with a compare-and-swap loop. Skipped positions add
// nothing, so the sums and their order are those of the full walk.
#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_KHR_shader_subgroup_vote : require
#if S4D_FLOAT_ATOMICS
#extension GL_EXT_shader_atomic_float : require
#endif
#include "s4d_splat.h"
#include "flat_group.glsl"
#include "splat_sample.glsl"
#if S4D_BLEND_UNROLL != 8
#error "main() calls accumulate() eight times per iteration"
#endif

layout(local_size_x = S4D_TILE_SIZE, local_size_y = S4D_TILE_SIZE) in;
layout(push_constant) uniform Push { RasterParams p; };
layout(std430, binding = S4D_B_RBWD_RANGES) readonly buffer Ranges { uvec2 ranges[]; };
layout(std430, binding = S4D_B_RBWD_GAUSSIAN_IDS) readonly buffer GaussianIds { uint gaussian_ids[]; };
layout(std430, binding = S4D_B_RBWD_XY) readonly buffer Xy { vec2 xy[]; };
layout(std430, binding = S4D_B_RBWD_CONIC_OPACITY) readonly buffer ConicOpacity { vec4 conic_opacity[]; };
layout(std430, binding = S4D_B_RBWD_COLOR_DEPTH) readonly buffer ColorDepth { vec4 color_depth[]; };
layout(std430, binding = S4D_B_RBWD_FINAL_T) readonly buffer FinalT { float final_t[]; };
layout(std430, binding = S4D_B_RBWD_LAST) readonly buffer Last { uint last_buf[]; };
layout(std430, binding = S4D_B_RBWD_V_RGB) readonly buffer VRgb { float v_rgb[]; };
layout(std430, binding = S4D_B_RBWD_V_ALPHA) readonly buffer VAlpha { float v_alpha_img[]; };
layout(std430, binding = S4D_B_RBWD_V_DEPTH) readonly buffer VDepth { float v_depth_img[]; };
#if S4D_FLOAT_ATOMICS
layout(std430, binding = S4D_B_RBWD_GRAD2D) buffer Grad2d { float grad2d[]; };
void add_grad(uint index, float value) { atomicAdd(grad2d[index], value); }
#else
layout(std430, binding = S4D_B_RBWD_GRAD2D) buffer Grad2d { uint grad2d[]; };
void add_grad(uint index, float value) {
  uint old = atomicOr(grad2d[index], 0u);  // an atomic read: a plain load would race the swaps
  for (;;) {
    uint seen = atomicCompSwap(grad2d[index], old, floatBitsToUint(uintBitsToFloat(old) + value));
    if (seen == old) break;
    old = seen;
  }
}
#endif

shared uint s_id[S4D_TILE_PIXELS];
shared vec2 s_xy[S4D_TILE_PIXELS];
shared vec4 s_conic_opacity[S4D_TILE_PIXELS];
shared vec4 s_color_depth[S4D_TILE_PIXELS];
shared uint s_max_last;

// This pixel's backward state.
vec2 centre;
uint last;
vec3 vc;                    // dL/d rgb of the pixel
float v_pix_alpha, v_pix_depth, bg_dot, T_final;
float T;                    // transmittance in front of the Gaussian after the current one
vec3 behind = vec3(0.0);    // colour blended behind the current Gaussian, per unit of T after it
float behind_depth = 0.0;

// The cotangents of entry j of the batch (list position `end - 1 - j`), reduced over the subgroup
// and added to grad2d by one lane. No loops inside: see S4D_BLEND_UNROLL.
void accumulate(uint j, uint batch, uint end) {
  if (j >= batch) return;  // uniform: every invocation has the same batch
  uint position = end - 1u - j;
  vec4 co = s_conic_opacity[j];
  SplatSample s = splat_sample(s_xy[j], co, centre);
  bool contributes = position < last && !s.skip;
  // Uniform within the subgroup: where no pixel of it meets this Gaussian (most listed pairs), the
  // gradient code below is skipped instead of executed under an all-false mask, and the reductions
  // inside stay legal.
  if (!subgroupAny(contributes)) return;
  vec2 g_xy = vec2(0.0);
  vec3 g_conic = vec3(0.0), g_rgb = vec3(0.0);
  float g_opacity = 0.0, g_depth = 0.0;
  if (contributes) {
    vec4 cd = s_color_depth[j];
    float T_i = T / (1.0 - s.alpha);
    float v_alpha = T_i * dot(cd.rgb - behind, vc) + T_i * (cd.w - behind_depth) * v_pix_depth +
                    T_final / (1.0 - s.alpha) * (v_pix_alpha - bg_dot);
    g_rgb = (s.alpha * T_i) * vc;
    g_depth = s.alpha * T_i * v_pix_depth;
    if (!s.clamped) {  // a capped alpha does not depend on conic, mean or opacity
      g_opacity = s.G * v_alpha;
      float v_power = co.w * s.G * v_alpha;
      g_xy = -v_power * vec2(co.x * s.d.x + co.y * s.d.y, co.y * s.d.x + co.z * s.d.y);
      g_conic = -v_power * vec3(0.5 * s.d.x * s.d.x, s.d.x * s.d.y, 0.5 * s.d.y * s.d.y);
    }
    behind = s.alpha * cd.rgb + (1.0 - s.alpha) * behind;
    behind_depth = s.alpha * cd.w + (1.0 - s.alpha) * behind_depth;
    T = T_i;
  }
  g_xy = subgroupAdd(g_xy);
  g_conic = subgroupAdd(g_conic);
  g_rgb = subgroupAdd(g_rgb);
  g_opacity = subgroupAdd(g_opacity);
  g_depth = subgroupAdd(g_depth);
  if (!subgroupElect()) return;
  uint base = s_id[j] * S4D_G2D_STRIDE;
  add_grad(base + S4D_G2D_XY, g_xy.x), add_grad(base + S4D_G2D_XY + 1, g_xy.y);
  add_grad(base + S4D_G2D_CONIC, g_conic.x), add_grad(base + S4D_G2D_CONIC + 1, g_conic.y);
  add_grad(base + S4D_G2D_CONIC + 2, g_conic.z);
  add_grad(base + S4D_G2D_OPACITY, g_opacity);
  add_grad(base + S4D_G2D_RGB, g_rgb.r), add_grad(base + S4D_G2D_RGB + 1, g_rgb.g);
  add_grad(base + S4D_G2D_RGB + 2, g_rgb.b);
  add_grad(base + S4D_G2D_DEPTH, g_depth);
}

void main() {
  uint tile = flat_group_id();
  if (tile >= p.size.z * p.size.w) return;  // whole workgroups only: barriers stay uniform
  uint lid = gl_LocalInvocationIndex;
  uvec2 pix = uvec2(tile % p.size.z, tile / p.size.z) * S4D_TILE_SIZE + gl_LocalInvocationID.xy;
  bool inside = pix.x < p.size.x && pix.y < p.size.y;
  centre = vec2(pix) + 0.5;
  uint o = pix.y * p.size.x + pix.x;
  uint range_begin = ranges[tile].x;

  last = inside ? last_buf[o] : 0u;
  T_final = inside ? final_t[o] : 1.0;
  vc = inside ? vec3(v_rgb[3u * o], v_rgb[3u * o + 1u], v_rgb[3u * o + 2u]) : vec3(0.0);
  v_pix_alpha = inside && (p.flags & S4D_RASTER_HAS_V_ALPHA) != 0u ? v_alpha_img[o] : 0.0;
  v_pix_depth = inside && (p.flags & S4D_RASTER_HAS_V_DEPTH) != 0u ? v_depth_img[o] : 0.0;
  bg_dot = dot(p.background.rgb, vc);
  T = T_final;

  if (lid == 0u) s_max_last = 0u;
  barrier();
  atomicMax(s_max_last, last);
  barrier();
  uint entries = s_max_last;
  uint subgroup_last = subgroupMax(last);

  for (uint end = entries; end > 0u; end -= min(end, uint(S4D_TILE_PIXELS))) {
    uint batch = min(end, uint(S4D_TILE_PIXELS));
    barrier();
    if (lid < batch) {  // s_*[j] holds list position end - 1 - j: back to front
      uint g = gaussian_ids[range_begin + end - 1u - lid];
      s_id[lid] = g;
      s_xy[lid] = xy[g];
      s_conic_opacity[lid] = conic_opacity[g];
      s_color_depth[lid] = color_depth[g];
    }
    barrier();
    // Entries at list positions >= subgroup_last meet no pixel of this subgroup: start past them.
    for (uint j = end - min(end, subgroup_last); j < batch; j += S4D_BLEND_UNROLL) {
      accumulate(j, batch, end), accumulate(j + 1u, batch, end);
      accumulate(j + 2u, batch, end), accumulate(j + 3u, batch, end);
      accumulate(j + 4u, batch, end), accumulate(j + 5u, batch, end);
      accumulate(j + 6u, batch, end), accumulate(j + 7u, batch, end);
    }
  }
}
