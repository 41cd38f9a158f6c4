// raster_bwd: same tiling as raster_fwd. Each pixel walks its tile's list back to front from its
// last contributor, recovering T_i = T_{i+1} / (1 - alpha_i) from the stored final transmittance
// (ALGORITHMS.md 1.6). An invocation takes S4D_RBWD_PIXELS pixels of a column. The workgroup loads the
// list in batches up to the tile's last contributor; each subgroup starts at its own last
// contributor (subgroupMax), and every invocation of a subgroup visits the same list position at
// the same step. Where no pixel of the subgroup meets the Gaussian, the gradient code is skipped (a
// uniform branch); otherwise the per-Gaussian cotangents are summed over the invocation's pixels,
// then over the subgroup, and added to global memory by the subgroup's lanes in parallel, lane i
// the values i, i + S, ...: with float atomics when the device has them (S4D_FLOAT_ATOMICS=1), else
// with a compare-and-swap loop. Skipped positions add nothing.
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
#extension GL_KHR_shader_subgroup_shuffle : require  // the style variant's reduce-scatter
#if S4D_FLOAT_ATOMICS
#extension GL_EXT_shader_atomic_float : require
#endif
#include "s4d_style_splat.h"
#include "flat_group.glsl"

// Each invocation takes S4D_RBWD_PIXELS pixels of a column (rows S4D_RBWD_PIXELS y ..): the per-pair
// subgroup reductions and atomics, which cost llvmpipe a loop over the lanes each, then serve
// S4D_RBWD_PIXELS times as many pixels (8 pixels beat 4, which beat 2, which beat 1, on
// lavapipe; docs/rasterizer.md). The per-pixel sums over an invocation's pixels come first.
layout(local_size_x = S4D_TILE_SIZE, local_size_y = S4D_TILE_SIZE / S4D_RBWD_PIXELS) in;  // S4D_RBWD_INVOCATIONS
// RBWD_EACH(F): F(k) for each of the invocation's pixels, written out (llvmpipe's loop cap).
#if S4D_RBWD_PIXELS == 8
#define RBWD_EACH(F) F(0) F(1) F(2) F(3) F(4) F(5) F(6) F(7)
#elif S4D_RBWD_PIXELS == 1
#define RBWD_EACH(F) F(0)
#else
#error "RBWD_EACH writes out 1 or 8 pixels"
#endif
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

// The fewest lanes a subgroup of this kernel has, set by the host (rasterizer.cpp, S4D_RBWD_SPEC_MIN_SUBGROUP);
// 1 is right on any device.
// Round r of the lane-parallel adds below is needed while r x MIN_SUBGROUP < count: a constant
// condition once specialised, so the unneeded rounds compile away. The rounds are written out, not
// looped: llvmpipe counts every loop iteration against its cap, an unrolled one included.
layout(constant_id = S4D_RBWD_SPEC_MIN_SUBGROUP) const uint MIN_SUBGROUP = 1u;
bool rbwd_round_needed(uint r, uint count) { return r * MIN_SUBGROUP < count; }

// Component c of v, c varying per lane. Selects, not v[c]: the atomics below pick their value by
// lane, and llvmpipe runs a dynamically indexed local array through memory, lane by lane.
float vec4_at(vec4 v, uint c) { return mix(mix(v.x, v.y, c == 1u), mix(v.z, v.w, c == 3u), c >= 2u); }

// One pixel's backward state.
struct Pixel {
  vec2 centre;            // (i + 0.5, j + 0.5)
  vec2 ray;               // camera-space ray at z = 1 (style)
  uint last;
  vec3 vc;                // dL/d rgb of the pixel
  float v_pix_alpha, v_pix_depth, bg_dot, T_final;
  float T;                // transmittance in front of the Gaussian after the current one
  vec3 behind;            // colour blended behind the current Gaussian, per unit of T after it
  float behind_depth;
};
Pixel px[S4D_RBWD_PIXELS];  // this invocation's pixels, a column

// Points raster_pair.glsl's sampling at pixel q.
void use_pixel(Pixel q) {
  centre = q.centre;
#if S4D_STYLE
  ray = q.ray;
#endif
}

// The current pair's cotangents, summed over this invocation's pixels.
vec2 g_xy;
vec3 g_conic, g_rgb;
float g_opacity, g_depth;

#if S4D_STYLE
vec4 v_w[S4D_STYLE_MLP_VEC4S];  // the current pair's weight cotangents, in the weights' vec4 layout

// Backward of style_mlp_fwd for output cotangent dz, added to v_w.
void mlp_bwd(Slot sl, StyleMlpEval m, vec4 dz) {
  vec4 dh2 = vec4(dot(sl.w[8], dz), dot(sl.w[9], dz), dot(sl.w[10], dz), dot(sl.w[11], dz));
  vec4 da2 = dh2 * m.h2 * (1.0 - m.h2);
  vec4 dh1 = vec4(dot(sl.w[3], da2), dot(sl.w[4], da2), dot(sl.w[5], da2), dot(sl.w[6], da2));
  vec4 da1 = dh1 * m.h1 * (1.0 - m.h1);
  v_w[0] += da1 * m.x.x, v_w[1] += da1 * m.x.y, v_w[2] += da1;
  v_w[3] += da2 * m.h1.x, v_w[4] += da2 * m.h1.y, v_w[5] += da2 * m.h1.z, v_w[6] += da2 * m.h1.w, v_w[7] += da2;
  v_w[8] += dz * m.h2.x, v_w[9] += dz * m.h2.y, v_w[10] += dz * m.h2.z, v_w[11] += dz * m.h2.w, v_w[12] += dz;
}

// Round r of the lane-parallel adds of the weight cotangents: value k = lane + r S (the weights'
// layout), if there is one.
void add_mlp(uint w, uint lane, uint size, uint r) {
  if (!rbwd_round_needed(r, S4D_STYLE_MLP_STRIDE)) return;
  uint k = lane + r * size, i = k >> 2u;
  vec4 v = v_w[0];
  v = mix(v, v_w[1], bvec4(i == 1u)), v = mix(v, v_w[2], bvec4(i == 2u)), v = mix(v, v_w[3], bvec4(i == 3u));
  v = mix(v, v_w[4], bvec4(i == 4u)), v = mix(v, v_w[5], bvec4(i == 5u)), v = mix(v, v_w[6], bvec4(i == 6u));
  v = mix(v, v_w[7], bvec4(i == 7u)), v = mix(v, v_w[8], bvec4(i == 8u)), v = mix(v, v_w[9], bvec4(i == 9u));
  v = mix(v, v_w[10], bvec4(i == 10u)), v = mix(v, v_w[11], bvec4(i == 11u)), v = mix(v, v_w[12], bvec4(i == 12u));
  if (k < uint(S4D_STYLE_MLP_STRIDE)) add_v_mlp(w + k, vec4_at(v, k & 3u));
}

// The style variant's 62 cotangents of a pair (52 weights, 10 screen-space), reduced over the
// subgroup and scattered in one pass: at each step a lane keeps half of its values and adds the
// other lane's copy of that half (subgroupShuffleXor), so after log2(S) steps each of the S lanes
// holds 64 / S sums, and 62 shuffles replace the 18 subgroupAdds' 62 reductions (on a GPU each is
// log2(S) shuffles: 5x fewer at S = 32). Values: rs[0 .. 12] the weights' vec4s, rs[13 .. 15]
// v_g2d. Needs every lane active and S = MIN_SUBGROUP, 2 .. 64 (checked by the caller); a device
// whose subgroups vary in size takes the subgroupAdd path below instead (tests run it on lavapipe
// by specialising a smaller MIN_SUBGROUP: RasterizerOptions::min_subgroup_lanes).
vec4 rs[16];

// Step with lane mask m over the first 2n vec4s: the lane with bit m keeps the upper n.
void rs_step(uint m, uint n) {
  bool upper = (gl_SubgroupInvocationID & m) != 0u;
#define RS_PAIR(i) if (i < n) { vec4 keep = upper ? rs[i + n] : rs[i], give = upper ? rs[i] : rs[i + n]; \
  rs[i] = keep + subgroupShuffleXor(give, m); }
  RS_PAIR(0u) RS_PAIR(1u) RS_PAIR(2u) RS_PAIR(3u) RS_PAIR(4u) RS_PAIR(5u) RS_PAIR(6u) RS_PAIR(7u)
}

// Adds value f of the 64 (rs's layout) to global memory.
void rs_add(uint f, float value, uint w, uint base) {
  if (f < uint(S4D_STYLE_MLP_STRIDE)) add_v_mlp(w + f, value);
  else if (f < uint(S4D_STYLE_MLP_STRIDE + S4D_G2D_STRIDE)) add_grad(base + f - uint(S4D_STYLE_MLP_STRIDE), value);
}

void reduce_scatter_add(uint w, uint base) {
  uint lane = gl_SubgroupInvocationID;
  // vec4 steps, the lane's block offset growing by n for each mask bit it has.
  uint block = 0u;
  if (MIN_SUBGROUP >= 2u) rs_step(1u, 8u), block += (lane & 1u) * 8u;
  if (MIN_SUBGROUP >= 4u) rs_step(2u, 4u), block += ((lane >> 1u) & 1u) * 4u;
  if (MIN_SUBGROUP >= 8u) rs_step(4u, 2u), block += ((lane >> 2u) & 1u) * 2u;
  if (MIN_SUBGROUP >= 16u) rs_step(8u, 1u), block += (lane >> 3u) & 1u;
  // Then within the lane's last vec4: halves (S >= 32), quarters (S = 64).
  if (MIN_SUBGROUP >= 32u) {
    bool hi = (lane & 16u) != 0u;
    vec2 keep = hi ? rs[0].zw : rs[0].xy, give = hi ? rs[0].xy : rs[0].zw;
    vec2 v = keep + subgroupShuffleXor(give, 16u);
    uint f = 4u * block + (hi ? 2u : 0u);
    if (MIN_SUBGROUP >= 64u) {
      bool odd = (lane & 32u) != 0u;
      rs_add(f + (odd ? 1u : 0u), (odd ? v.y : v.x) + subgroupShuffleXor(odd ? v.x : v.y, 32u), w, base);
    } else {
      rs_add(f, v.x, w, base), rs_add(f + 1u, v.y, w, base);
    }
    return;
  }
  // S <= 16: 16 / S vec4s left, blocks block .. block + 16 / S - 1.
  uint left = 16u / MIN_SUBGROUP;
#define RS_ADD(i) if (i < left) { rs_add(4u * (block + i), rs[i].x, w, base); rs_add(4u * (block + i) + 1u, rs[i].y, w, base); \
  rs_add(4u * (block + i) + 2u, rs[i].z, w, base); rs_add(4u * (block + i) + 3u, rs[i].w, w, base); }
  RS_ADD(0u) RS_ADD(1u) RS_ADD(2u) RS_ADD(3u) RS_ADD(4u) RS_ADD(5u) RS_ADD(6u) RS_ADD(7u)
}
#endif

vec4 v_g2d[3];  // the current pair's screen-space cotangents in grad2d's layout (S4D_G2D_*), padded

// Round r of the lane-parallel adds of the screen-space cotangents: value k = lane + r S, if there is one.
void add_g2d(uint base, uint lane, uint size, uint r) {
  if (!rbwd_round_needed(r, S4D_G2D_STRIDE)) return;
  uint k = lane + r * size, i = k >> 2u;
  vec4 v = mix(mix(v_g2d[0], v_g2d[1], bvec4(i == 1u)), v_g2d[2], bvec4(i == 2u));
  if (k < uint(S4D_G2D_STRIDE)) add_grad(base + k, vec4_at(v, k & 3u));
}

// Adds pixel q's cotangents of the entry in slot sl (sample s, which q meets in front of its last
// contributor) to the pair's sums, and steps q's state past the entry.
void pixel_pair(Slot sl, PairSample s, inout Pixel q) {
  vec4 cd = sl.color_depth;
  vec3 c = pair_color(sl, s);
  float alpha = s.b.alpha;
  float T_i = q.T / (1.0 - alpha);
  float v_alpha = T_i * dot(c - q.behind, q.vc) + T_i * (cd.w - q.behind_depth) * q.v_pix_depth +
                  q.T_final / (1.0 - alpha) * (q.v_pix_alpha - q.bg_dot);
  vec3 p_rgb = (alpha * T_i) * q.vc;
  float p_opacity = 0.0;
  g_rgb += p_rgb;
  g_depth += alpha * T_i * q.v_pix_depth;
  if (!s.b.clamped) {  // a capped alpha depends on neither the conic, the mean nor the opacity
    p_opacity = s.b.G * v_alpha;
    float v_power = s.opacity * s.b.G * v_alpha;
    vec4 co = sl.conic_opacity;
    vec2 d = s.b.d;
    g_opacity += p_opacity;
    g_xy += -v_power * vec2(co.x * d.x + co.y * d.y, co.y * d.x + co.z * d.y);
    g_conic += -v_power * vec3(0.5 * d.x * d.x, d.x * d.y, 0.5 * d.y * d.y);
  }
#if S4D_STYLE
  mlp_bwd(sl, s.m, s.m.s * (1.0 - s.m.s) * vec4(2.0 * p_rgb, p_opacity));
#endif
  q.behind = alpha * c + (1.0 - alpha) * q.behind;
  q.behind_depth = alpha * cd.w + (1.0 - alpha) * q.behind_depth;
  q.T = T_i;
}

// The cotangents of entry j of the batch (list position `end - 1 - j`), reduced over the subgroup
// and added to global memory by its lanes in parallel. No loops inside: see S4D_RASTER_UNROLL.
void accumulate(uint j, uint batch, uint end) {
  if (j >= batch) return;  // uniform: every invocation has the same batch
  uint position = end - 1u - j;
  Slot sl = slot_load(j);  // once for all the invocation's pixels
#define RBWD_SAMPLE(k) use_pixel(px[k]); PairSample s##k = pair_sample(sl); \
  bool c##k = position < px[k].last && !s##k.b.skip; any_pixel = any_pixel || c##k;
  bool any_pixel = false;
  RBWD_EACH(RBWD_SAMPLE)
  if (!subgroupAny(any_pixel)) return;
  g_xy = vec2(0.0), g_conic = vec3(0.0), g_rgb = vec3(0.0), g_opacity = 0.0, g_depth = 0.0;
#if S4D_STYLE
  v_w = vec4[S4D_STYLE_MLP_VEC4S](vec4(0.0), vec4(0.0), vec4(0.0), vec4(0.0), vec4(0.0), vec4(0.0), vec4(0.0),
                                  vec4(0.0), vec4(0.0), vec4(0.0), vec4(0.0), vec4(0.0), vec4(0.0));
#endif
#define RBWD_PAIR(k) if (c##k) pixel_pair(sl, s##k, px[k]);
  RBWD_EACH(RBWD_PAIR)
#if S4D_STYLE
  if (gl_SubgroupSize == MIN_SUBGROUP && MIN_SUBGROUP >= 2u && MIN_SUBGROUP <= 64u) {  // uniform
    rs[0] = v_w[0], rs[1] = v_w[1], rs[2] = v_w[2], rs[3] = v_w[3], rs[4] = v_w[4], rs[5] = v_w[5], rs[6] = v_w[6];
    rs[7] = v_w[7], rs[8] = v_w[8], rs[9] = v_w[9], rs[10] = v_w[10], rs[11] = v_w[11], rs[12] = v_w[12];
    rs[13] = vec4(g_xy, g_conic.xy), rs[14] = vec4(g_conic.z, g_opacity, g_rgb.rg), rs[15] = vec4(g_rgb.b, g_depth, 0.0, 0.0);
    reduce_scatter_add(s_id[j] * S4D_STYLE_MLP_STRIDE, s_id[j] * S4D_G2D_STRIDE);
    return;
  }
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
  // Every lane holds the sums: lane i adds values i, i + S, ... (S the subgroup size), so one
  // atomic instruction adds up to S values. llvmpipe runs each atomic instruction as a loop over
  // all the subgroup's lanes however few are active: at S = 8 this is 2 such loops instead of 10
  // (style: 9 instead of 62). Every lane is active here (the walk is uniform in the subgroup).
  // A subgroup wider than the workgroup (64 lanes, 32 invocations) is partial: lanes 0 .. 31.
  uint lane = gl_SubgroupInvocationID, size = min(gl_SubgroupSize, uint(S4D_RBWD_INVOCATIONS));
  v_g2d[0] = vec4(g_xy, g_conic.xy), v_g2d[1] = vec4(g_conic.z, g_opacity, g_rgb.rg);
  v_g2d[2] = vec4(g_rgb.b, g_depth, 0.0, 0.0);
  uint base = s_id[j] * S4D_G2D_STRIDE;
  add_g2d(base, lane, size, 0u), add_g2d(base, lane, size, 1u), add_g2d(base, lane, size, 2u);
  add_g2d(base, lane, size, 3u), add_g2d(base, lane, size, 4u), add_g2d(base, lane, size, 5u);
  add_g2d(base, lane, size, 6u), add_g2d(base, lane, size, 7u), add_g2d(base, lane, size, 8u);
  add_g2d(base, lane, size, 9u);
#if S4D_STYLE
  uint w = s_id[j] * S4D_STYLE_MLP_STRIDE;
  add_mlp(w, lane, size, 0u), add_mlp(w, lane, size, 1u), add_mlp(w, lane, size, 2u), add_mlp(w, lane, size, 3u);
  add_mlp(w, lane, size, 4u), add_mlp(w, lane, size, 5u), add_mlp(w, lane, size, 6u), add_mlp(w, lane, size, 7u);
  add_mlp(w, lane, size, 8u), add_mlp(w, lane, size, 9u), add_mlp(w, lane, size, 10u), add_mlp(w, lane, size, 11u);
  add_mlp(w, lane, size, 12u), add_mlp(w, lane, size, 13u), add_mlp(w, lane, size, 14u), add_mlp(w, lane, size, 15u);
  add_mlp(w, lane, size, 16u), add_mlp(w, lane, size, 17u), add_mlp(w, lane, size, 18u), add_mlp(w, lane, size, 19u);
  add_mlp(w, lane, size, 20u), add_mlp(w, lane, size, 21u), add_mlp(w, lane, size, 22u), add_mlp(w, lane, size, 23u);
  add_mlp(w, lane, size, 24u), add_mlp(w, lane, size, 25u), add_mlp(w, lane, size, 26u), add_mlp(w, lane, size, 27u);
  add_mlp(w, lane, size, 28u), add_mlp(w, lane, size, 29u), add_mlp(w, lane, size, 30u), add_mlp(w, lane, size, 31u);
  add_mlp(w, lane, size, 32u), add_mlp(w, lane, size, 33u), add_mlp(w, lane, size, 34u), add_mlp(w, lane, size, 35u);
  add_mlp(w, lane, size, 36u), add_mlp(w, lane, size, 37u), add_mlp(w, lane, size, 38u), add_mlp(w, lane, size, 39u);
  add_mlp(w, lane, size, 40u), add_mlp(w, lane, size, 41u), add_mlp(w, lane, size, 42u), add_mlp(w, lane, size, 43u);
  add_mlp(w, lane, size, 44u), add_mlp(w, lane, size, 45u), add_mlp(w, lane, size, 46u), add_mlp(w, lane, size, 47u);
  add_mlp(w, lane, size, 48u), add_mlp(w, lane, size, 49u), add_mlp(w, lane, size, 50u), add_mlp(w, lane, size, 51u);
#endif
}

#if S4D_STYLE
#include "raster_walk.glsl"

// Marks slot j in `bits` when it may meet one of this invocation's pixels in front of its last contributor.
void accumulate_mark(uint j, uint batch, uint end, inout uvec2 bits) {
  if (j >= batch) return;  // uniform: every invocation has the same batch
  uint position = end - 1u - j;
  bool meets = false;
  Slot sl = slot_load_bound(j);
#define RBWD_BOUND(k) use_pixel(px[k]); meets = meets || (position < px[k].last && !pair_bound(sl).b.skip);
  RBWD_EACH(RBWD_BOUND)
  raster_walk_mark(bits, j, meets);
}

// Accumulates the next marked slot, if any, and unmarks it.
void accumulate_next(inout uvec2 todo, uint batch, uint end) {
  if (todo == uvec2(0u)) return;  // uniform: the same todo in the whole subgroup
  accumulate(raster_walk_pop(todo), batch, end);
}
#endif

// Pixel pix's state from the forward's outputs and the image cotangents; a pixel outside the
// image has no contributor.
Pixel load_pixel(uvec2 pix) {
  Pixel q;
  bool inside = pix.x < p.size.x && pix.y < p.size.y;
  uint o = pix.y * p.size.x + pix.x;
  q.centre = vec2(pix) + 0.5;
  q.ray = (q.centre - p.intrinsics.zw) / p.intrinsics.xy;
  q.last = inside ? last_buf[o] : 0u;
  q.T_final = inside ? final_t[o] : 1.0;
  q.vc = inside ? vec3(v_rgb[3u * o], v_rgb[3u * o + 1u], v_rgb[3u * o + 2u]) : vec3(0.0);
  q.v_pix_alpha = inside && (p.flags & S4D_RASTER_HAS_V_ALPHA) != 0u ? v_alpha_img[o] : 0.0;
  q.v_pix_depth = inside && (p.flags & S4D_RASTER_HAS_V_DEPTH) != 0u ? v_depth_img[o] : 0.0;
  q.bg_dot = dot(p.background.rgb, q.vc);
  q.T = q.T_final;
  q.behind = vec3(0.0), q.behind_depth = 0.0;
  return q;
}

void main() {
  uint tile = flat_group_id();
  if (tile >= p.size.z * p.size.w) return;  // whole workgroups only: barriers stay uniform
  uint lid = gl_LocalInvocationIndex;
  uvec2 origin = uvec2(tile % p.size.z, tile / p.size.z) * S4D_TILE_SIZE;
  uvec2 local = uvec2(gl_LocalInvocationID.x, S4D_RBWD_PIXELS * gl_LocalInvocationID.y);
  uint last = 0u;
#define RBWD_LOAD(k) px[k] = load_pixel(origin + local + uvec2(0u, k)); last = max(last, px[k].last);
  RBWD_EACH(RBWD_LOAD)
  uint range_begin = ranges[tile].x;

  if (lid == 0u) s_max_last = 0u;
  barrier();
  atomicMax(s_max_last, last);
  barrier();
  uint entries = s_max_last;
  uint subgroup_last = subgroupMax(last);

  for (uint end = entries; end > 0u; end -= min(end, uint(S4D_RASTER_BATCH))) {
    uint batch = min(end, uint(S4D_RASTER_BATCH));
    barrier();
    // Slot j: list position end - 1 - j. S4D_RBWD_PIXELS loads per invocation: a fraction of the
    // forward's invocations.
    const uint wg = uint(S4D_RBWD_INVOCATIONS);
#define RBWD_BATCH(k) raster_load_batch(lid + k * wg, range_begin + end - 1u, true, batch);
    RBWD_EACH(RBWD_BATCH)
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
