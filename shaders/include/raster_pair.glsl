// One (pixel, list entry) pair of the rasterizer family: the sampling and colour policy in which the
// plain and style variants (raster_variant.glsl) differ, shared by raster_fwd and raster_bwd so their
// skip decisions agree bit for bit. Plain: the standard sample (splat_sample.glsl) and the
// Gaussian's colour. Style (ALGORITHMS.md 4.3-4.4): GOF's depth of maximum response t* along the
// pixel ray, its depth feature, the Gaussian's MLP on (time, feature), the standard sample with
// opacity o' = o + dO and colour c + dRGB. Every value that feeds a skip decision is `precise`, so
// the compiler cannot contract the two kernels' copies differently. The includer declares the batch
// arrays first (raster_batch.glsl, or the blend_ceiling benchmark's own) and, for style, the
// push-constant block `p` (RasterParams).
#ifndef RASTER_PAIR_GLSL
#define RASTER_PAIR_GLSL
#include "raster_variant.glsl"
#include "splat_sample.glsl"

vec2 centre;  // this pixel's centre, (i + 0.5, j + 0.5)

// One batch slot's data in registers, loaded once per slot (slot_load) and read by every pixel
// that meets it: llvmpipe runs each shared-memory load as a loop over the subgroup's lanes, so
// loading per pixel (and per use) multiplied the kernels' cost.
struct Slot {
  vec2 xy;
  vec4 conic_opacity;  // (conic, opacity o)
  vec4 color_depth;    // (colour c, camera-space depth z)
#if S4D_STYLE
  vec4 w[S4D_STYLE_MLP_VEC4S];  // the MLP's weights (s4d_style_splat.h's layout)
  vec4 q0, q1, q2;              // the quadric: (Q00 Q01 Q02 Q11), (Q12 Q22 b0 b1), (b2, 0, 0, 0)
#endif
};

// The inputs of the cheap bound (pair_bound) only.
Slot slot_load_bound(uint j) {
  Slot s;
  s.xy = s_xy[j];
  s.conic_opacity = s_conic_opacity[j];
  return s;
}

// Slot j's data.
Slot slot_load(uint j) {
  Slot s = slot_load_bound(j);
  s.color_depth = s_color_depth[j];
#if S4D_STYLE
  uint base = uint(S4D_STYLE_SLOT_PARTS) * j;
#define SLOT_PART(k) s.w[k] = s_style[base + uint(k)];
  SLOT_PART(0) SLOT_PART(1) SLOT_PART(2) SLOT_PART(3) SLOT_PART(4) SLOT_PART(5) SLOT_PART(6)
  SLOT_PART(7) SLOT_PART(8) SLOT_PART(9) SLOT_PART(10) SLOT_PART(11) SLOT_PART(12)
  s.q0 = s_style[base + 13u], s.q1 = s_style[base + 14u], s.q2 = s_style[base + 15u];
#endif
  return s;
}

#if S4D_STYLE
vec2 ray;     // its camera-space ray (x, y) at z = 1

// The MLP's activations on one pair: inputs (after the optional sigmoid), both hidden layers and
// s = sigmoid(z) of the outputs.
struct StyleMlpEval {
  vec2 x;
  vec4 h1, h2, s;
};

StyleMlpEval style_mlp_fwd(Slot sl, vec2 x) {
  StyleMlpEval m;
  m.x = x;
  precise vec4 a1 = sl.w[0] * x.x + sl.w[1] * x.y + sl.w[2];
  precise vec4 h1 = 1.0 / (1.0 + exp(-a1));
  precise vec4 a2 = mat4(sl.w[3], sl.w[4], sl.w[5], sl.w[6]) * h1 + sl.w[7];
  precise vec4 h2 = 1.0 / (1.0 + exp(-a2));
  precise vec4 z = mat4(sl.w[8], sl.w[9], sl.w[10], sl.w[11]) * h2 + sl.w[12];
  precise vec4 s = 1.0 / (1.0 + exp(-z));
  m.h1 = h1, m.h2 = h2, m.s = s;
  return m;
}

// The MLP's depth input for the slot: t* = -(b.r) / (r^T Q r) with r = (ray, 1). A degenerate or
// overflowing quadric falls back to the centre depth z_i.
float style_depth_feature(Slot sl) {
  vec4 q0 = sl.q0, q1 = sl.q1;  // (Q00 Q01 Q02 Q11), (Q12 Q22 b0 b1)
  float b2 = sl.q2.x, z = sl.color_depth.w;
  precise float A = q0.x * ray.x * ray.x + q0.w * ray.y * ray.y + q1.y +
                    2.0 * (q0.y * ray.x * ray.y + q0.z * ray.x + q1.x * ray.y);
  precise float bd = q1.z * ray.x + q1.w * ray.y + b2;
  precise float t = -bd / A;
  if (!(A > 0.0) || isinf(t) || isnan(t)) t = z;
  if (p.depth_mode == S4D_STYLE_DEPTH_NDC) {
    precise float tc = clamp(t, S4D_STYLE_NDC_NEAR, S4D_STYLE_NDC_FAR);
    precise float m = S4D_STYLE_NDC_FAR / (S4D_STYLE_NDC_FAR - S4D_STYLE_NDC_NEAR) * (1.0 - S4D_STYLE_NDC_NEAR / tc);
    return m;
  }
  precise float rel = (t - z) * p.depth_scale;
  return rel;
}
#endif

struct PairSample {
  SplatSample b;  // the standard sample with the pair's opacity (skip, clamped, alpha, G, d)
  float opacity;  // the pair's opacity: o, or o' = o + dO
#if S4D_STYLE
  vec3 drgb;      // colour offset in (-1, 1)
  StyleMlpEval m;
#endif
};

// A cheap bound on the pair's sample (slot_load_bound's fields only): it skips no pair that
// pair_sample() keeps. Plain: the sample itself. Style: the sample with opacity o + 0.5, without
// the MLP; dO < 0.5 and float rounding is monotone, so (o + 0.5) G < 1/255 implies o' G < 1/255
// (and power > 0 is the same test). A per-Gaussian bound on dO by interval arithmetic through its
// MLP was tried: the same images, 10-15 % slower renders of a trained run (its cost per batch
// outweighed the pairs it spared).
PairSample pair_bound(Slot sl) {
  PairSample s;
  vec4 co = sl.conic_opacity;
#if S4D_STYLE
  s.b = splat_sample(sl.xy, vec4(co.xyz, co.w + 0.5), centre);
#else
  s.b = splat_sample(sl.xy, co, centre);
  s.opacity = co.w;
#endif
  return s;
}

// The pair's sample. Style: the MLP on (time, depth feature), then the sample with o' = o + dO.
PairSample pair_sample(Slot sl) {
#if S4D_STYLE
  PairSample s;
  vec4 co = sl.conic_opacity;
  precise vec2 x = vec2(p.time, style_depth_feature(sl));
  if ((p.flags & S4D_STYLE_INPUT_SIGMOID) != 0u) x = 1.0 / (1.0 + exp(-x));
  s.m = style_mlp_fwd(sl, x);
  s.drgb = 2.0 * s.m.s.rgb - 1.0;
  precise float opacity = co.w + (s.m.s.w - 0.5);
  s.opacity = opacity;
  s.b = splat_sample(sl.xy, vec4(co.xyz, opacity), centre);
  return s;
#else
  return pair_bound(sl);
#endif
}

// The colour the pair blends: c, or c + dRGB.
vec3 pair_color(Slot sl, PairSample s) {
#if S4D_STYLE
  return sl.color_depth.rgb + s.drgb;
#else
  return sl.color_depth.rgb;
#endif
}

#endif  // RASTER_PAIR_GLSL
