// raster_bwd: same tiling as raster_fwd. Each pixel walks its tile's list back to front from its
// last contributor, recovering T_i = T_{i+1} / (1 - alpha_i) from the stored final transmittance
// (ALGORITHMS.md 1.6). The workgroup loads the list in batches up to the tile's last contributor;
// each subgroup starts at its own last contributor (subgroupMax), and every invocation of a
// subgroup visits the same list position at the same step. Where no pixel of the subgroup meets the
// Gaussian, the gradient code is skipped (a uniform branch); otherwise the per-Gaussian cotangents
// are summed over the subgroup and one lane adds them to global memory: with float atomics when the
// device has them (S4D_FLOAT_ATOMICS=1), else with a compare-and-swap loop. Skipped positions add
// nothing, so the sums and their order are those of the full walk.
// The style variant (S4D_STYLE=1) re-evaluates each pair's MLP (raster_pair.glsl): the colour
// cotangent g_c = alpha T dL/dC goes to c_i unchanged, dL/do' = G dL/dalpha to the base opacity, the
// mean and conic cotangents use o' in place of o, and dL/dz = sigmoid'(z) (2 g_c, dL/do') flows back
// through the MLP to its 52 weights, summed over the subgroup and added like grad2d. t* and the time
// are inputs only (no gradient).
#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_KHR_shader_subgroup_vote : require
#if S4D_FLOAT_ATOMICS
#extension GL_EXT_shader_atomic_float : require
#endif
#include "s4d_style_splat.h"
#include "flat_group.glsl"

layout(local_size_x = S4D_TILE_SIZE, local_size_y = S4D_TILE_SIZE) in;
layout(push_constant) uniform Push { RasterParams p; };
#include "raster_batch.glsl"
#include "raster_pair.glsl"
layout(std430, binding = S4D_B_RBWD_FINAL_T) readonly buffer FinalT { float final_t[]; };
layout(std430, binding = S4D_B_RBWD_LAST) readonly buffer Last { uint last_buf[]; };
layout(std430, binding = S4D_B_RBWD_V_RGB) readonly buffer VRgb { float v_rgb[]; };
layout(std430, binding = S4D_B_RBWD_V_ALPHA) readonly buffer VAlpha { float v_alpha_img[]; };
layout(std430, binding = S4D_B_RBWD_V_DEPTH) readonly buffer VDepth { float v_depth_img[]; };
#if S4D_FLOAT_ATOMICS
layout(std430, binding = S4D_B_RBWD_GRAD2D) buffer Grad2d { float grad2d[]; };
void add_grad(uint index, float value) { atomicAdd(grad2d[index], value); }
#if S4D_STYLE
layout(std430, binding = S4D_B_RBWD_V_STYLE_MLP) buffer VStyleMlp { float v_mlp[]; };
void add_v_mlp(uint index, float value) { atomicAdd(v_mlp[index], value); }
#endif
#else
// Compare-and-swap adds; the first read is atomic, as a plain load would race the swaps.
layout(std430, binding = S4D_B_RBWD_GRAD2D) buffer Grad2d { uint grad2d[]; };
void add_grad(uint index, float value) {
  uint old = atomicOr(grad2d[index], 0u);
  for (;;) {
    uint seen = atomicCompSwap(grad2d[index], old, floatBitsToUint(uintBitsToFloat(old) + value));
    if (seen == old) break;
    old = seen;
  }
}
#if S4D_STYLE
layout(std430, binding = S4D_B_RBWD_V_STYLE_MLP) buffer VStyleMlp { uint v_mlp[]; };
void add_v_mlp(uint index, float value) {
  uint old = atomicOr(v_mlp[index], 0u);
  for (;;) {
    uint seen = atomicCompSwap(v_mlp[index], old, floatBitsToUint(uintBitsToFloat(old) + value));
    if (seen == old) break;
    old = seen;
  }
}
#endif
#endif

shared uint s_max_last;

// This pixel's backward state.
uint last;
vec3 vc;                    // dL/d rgb of the pixel
float v_pix_alpha, v_pix_depth, bg_dot, T_final;
float T;                    // transmittance in front of the Gaussian after the current one
vec3 behind = vec3(0.0);    // colour blended behind the current Gaussian, per unit of T after it
float behind_depth = 0.0;

#if S4D_STYLE
vec4 v_w[S4D_STYLE_MLP_VEC4S];  // the current pair's weight cotangents, in the weights' vec4 layout

// Backward of style_mlp_fwd for output cotangent dz into v_w.
void mlp_bwd(uint j, StyleMlpEval m, vec4 dz) {
  uint w = uint(S4D_STYLE_MLP_VEC4S) * j;
  vec4 dh2 = vec4(dot(s_mlp[w + 8u], dz), dot(s_mlp[w + 9u], dz), dot(s_mlp[w + 10u], dz), dot(s_mlp[w + 11u], dz));
  vec4 da2 = dh2 * m.h2 * (1.0 - m.h2);
  vec4 dh1 = vec4(dot(s_mlp[w + 3u], da2), dot(s_mlp[w + 4u], da2), dot(s_mlp[w + 5u], da2), dot(s_mlp[w + 6u], da2));
  vec4 da1 = dh1 * m.h1 * (1.0 - m.h1);
  v_w[0] = da1 * m.x.x, v_w[1] = da1 * m.x.y, v_w[2] = da1;
  v_w[3] = da2 * m.h1.x, v_w[4] = da2 * m.h1.y, v_w[5] = da2 * m.h1.z, v_w[6] = da2 * m.h1.w, v_w[7] = da2;
  v_w[8] = dz * m.h2.x, v_w[9] = dz * m.h2.y, v_w[10] = dz * m.h2.z, v_w[11] = dz * m.h2.w, v_w[12] = dz;
}

void add_v_mlp4(uint index, vec4 v) {
  add_v_mlp(index, v.x), add_v_mlp(index + 1u, v.y), add_v_mlp(index + 2u, v.z), add_v_mlp(index + 3u, v.w);
}
#endif

// The cotangents of entry j of the batch (list position `end - 1 - j`), reduced over the subgroup
// and added to global memory by one lane. No loops inside: see S4D_RASTER_UNROLL.
void accumulate(uint j, uint batch, uint end) {
  if (j >= batch) return;  // uniform: every invocation has the same batch
  uint position = end - 1u - j;
  PairSample s = pair_sample(j);
  bool contributes = position < last && !s.b.skip;
  // Uniform within the subgroup: where no pixel of it meets this Gaussian (most listed pairs), the
  // gradient code below is skipped instead of executed under an all-false mask, and the reductions
  // inside stay legal.
  if (!subgroupAny(contributes)) return;
#if S4D_STYLE
  StyleMlpEval m = StyleMlpEval(vec2(0.0), vec4(0.0), vec4(0.0), vec4(0.0));  // with dz = 0: zero cotangents
  vec4 dz = vec4(0.0);
#endif
  vec2 g_xy = vec2(0.0);
  vec3 g_conic = vec3(0.0), g_rgb = vec3(0.0);
  float g_opacity = 0.0, g_depth = 0.0;
  if (contributes) {
    vec4 cd = s_color_depth[j];
    vec3 c = pair_color(j, s);
    float alpha = s.b.alpha;
    float T_i = T / (1.0 - alpha);
    float v_alpha = T_i * dot(c - behind, vc) + T_i * (cd.w - behind_depth) * v_pix_depth +
                    T_final / (1.0 - alpha) * (v_pix_alpha - bg_dot);
    g_rgb = (alpha * T_i) * vc;
    g_depth = alpha * T_i * v_pix_depth;
    if (!s.b.clamped) {  // a capped alpha depends on neither the conic, the mean nor the opacity
      g_opacity = s.b.G * v_alpha;
      float v_power = s.opacity * s.b.G * v_alpha;
      vec4 co = s_conic_opacity[j];
      vec2 d = s.b.d;
      g_xy = -v_power * vec2(co.x * d.x + co.y * d.y, co.y * d.x + co.z * d.y);
      g_conic = -v_power * vec3(0.5 * d.x * d.x, d.x * d.y, 0.5 * d.y * d.y);
    }
#if S4D_STYLE
    m = s.m;
    dz = m.s * (1.0 - m.s) * vec4(2.0 * g_rgb, g_opacity);
#endif
    behind = alpha * c + (1.0 - alpha) * behind;
    behind_depth = alpha * cd.w + (1.0 - alpha) * behind_depth;
    T = T_i;
  }
#if S4D_STYLE
  mlp_bwd(j, m, dz);
#endif
  g_xy = subgroupAdd(g_xy);
  g_conic = subgroupAdd(g_conic);
  g_rgb = subgroupAdd(g_rgb);
  g_opacity = subgroupAdd(g_opacity);
  g_depth = subgroupAdd(g_depth);
#if S4D_STYLE
  v_w[0] = subgroupAdd(v_w[0]), v_w[1] = subgroupAdd(v_w[1]), v_w[2] = subgroupAdd(v_w[2]);
  v_w[3] = subgroupAdd(v_w[3]), v_w[4] = subgroupAdd(v_w[4]), v_w[5] = subgroupAdd(v_w[5]);
  v_w[6] = subgroupAdd(v_w[6]), v_w[7] = subgroupAdd(v_w[7]), v_w[8] = subgroupAdd(v_w[8]);
  v_w[9] = subgroupAdd(v_w[9]), v_w[10] = subgroupAdd(v_w[10]), v_w[11] = subgroupAdd(v_w[11]);
  v_w[12] = subgroupAdd(v_w[12]);
#endif
  if (!subgroupElect()) return;
  uint base = s_id[j] * S4D_G2D_STRIDE;
  add_grad(base + S4D_G2D_XY, g_xy.x), add_grad(base + S4D_G2D_XY + 1, g_xy.y);
  add_grad(base + S4D_G2D_CONIC, g_conic.x), add_grad(base + S4D_G2D_CONIC + 1, g_conic.y);
  add_grad(base + S4D_G2D_CONIC + 2, g_conic.z);
  add_grad(base + S4D_G2D_OPACITY, g_opacity);
  add_grad(base + S4D_G2D_RGB, g_rgb.r), add_grad(base + S4D_G2D_RGB + 1, g_rgb.g);
  add_grad(base + S4D_G2D_RGB + 2, g_rgb.b);
  add_grad(base + S4D_G2D_DEPTH, g_depth);
#if S4D_STYLE
  uint w = s_id[j] * S4D_STYLE_MLP_STRIDE;
  add_v_mlp4(w, v_w[0]), add_v_mlp4(w + 4u, v_w[1]), add_v_mlp4(w + 8u, v_w[2]), add_v_mlp4(w + 12u, v_w[3]);
  add_v_mlp4(w + 16u, v_w[4]), add_v_mlp4(w + 20u, v_w[5]), add_v_mlp4(w + 24u, v_w[6]);
  add_v_mlp4(w + 28u, v_w[7]), add_v_mlp4(w + 32u, v_w[8]), add_v_mlp4(w + 36u, v_w[9]);
  add_v_mlp4(w + 40u, v_w[10]), add_v_mlp4(w + 44u, v_w[11]), add_v_mlp4(w + 48u, v_w[12]);
#endif
}

#if S4D_STYLE
#include "raster_walk.glsl"

// Marks slot j in `bits` when it may meet this pixel in front of its last contributor.
void accumulate_mark(uint j, uint batch, uint end, inout uvec2 bits) {
  if (j >= batch) return;  // uniform: every invocation has the same batch
  raster_walk_mark(bits, j, end - 1u - j < last && !pair_bound(j).b.skip);
}

// Accumulates the next marked slot, if any, and unmarks it.
void accumulate_next(inout uvec2 todo, uint batch, uint end) {
  if (todo == uvec2(0u)) return;  // uniform: the same todo in the whole subgroup
  accumulate(raster_walk_pop(todo), batch, end);
}
#endif

void main() {
  uint tile = flat_group_id();
  if (tile >= p.size.z * p.size.w) return;  // whole workgroups only: barriers stay uniform
  uint lid = gl_LocalInvocationIndex;
  uvec2 pix = uvec2(tile % p.size.z, tile / p.size.z) * S4D_TILE_SIZE + gl_LocalInvocationID.xy;
  bool inside = pix.x < p.size.x && pix.y < p.size.y;
  centre = vec2(pix) + 0.5;
#if S4D_STYLE
  ray = (centre - p.intrinsics.zw) / p.intrinsics.xy;
#endif
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

  for (uint end = entries; end > 0u; end -= min(end, uint(S4D_RASTER_BATCH))) {
    uint batch = min(end, uint(S4D_RASTER_BATCH));
    barrier();
    raster_load_batch(lid, range_begin + end - 1u, true, batch);  // slot j: list position end - 1 - j
    barrier();
    // Entries at list positions >= subgroup_last meet no pixel of this subgroup: start past them.
    uint first = end - min(end, subgroup_last);
#if S4D_STYLE
    // The compacted walk (raster_walk.glsl): mark the slots a pixel of this subgroup meets, visit those.
    uvec2 bits = uvec2(0u);
    for (uint j = first; j < batch; j += S4D_RASTER_MARK_UNROLL) {
      accumulate_mark(j, batch, end, bits), accumulate_mark(j + 1u, batch, end, bits);
      accumulate_mark(j + 2u, batch, end, bits), accumulate_mark(j + 3u, batch, end, bits);
      accumulate_mark(j + 4u, batch, end, bits), accumulate_mark(j + 5u, batch, end, bits);
      accumulate_mark(j + 6u, batch, end, bits), accumulate_mark(j + 7u, batch, end, bits);
    }
    uvec2 todo = raster_walk_todo(bits);
    while (todo != uvec2(0u)) {
      accumulate_next(todo, batch, end), accumulate_next(todo, batch, end);
      accumulate_next(todo, batch, end), accumulate_next(todo, batch, end);
    }
#else
    for (uint j = first; j < batch; j += S4D_RASTER_UNROLL) {
      accumulate(j, batch, end), accumulate(j + 1u, batch, end);
      accumulate(j + 2u, batch, end), accumulate(j + 3u, batch, end);
      accumulate(j + 4u, batch, end), accumulate(j + 5u, batch, end);
      accumulate(j + 6u, batch, end), accumulate(j + 7u, batch, end);
    }
#endif
  }
}
