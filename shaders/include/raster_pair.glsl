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

#if S4D_STYLE
vec2 ray;     // its camera-space ray (x, y) at z = 1

// The MLP's activations on one pair: inputs (after the optional sigmoid), both hidden layers and
// s = sigmoid(z) of the outputs.
struct StyleMlpEval {
  vec2 x;
  vec4 h1, h2, s;
};

StyleMlpEval style_mlp_fwd(uint j, vec2 x) {
  uint w = uint(S4D_STYLE_MLP_VEC4S) * j;
  StyleMlpEval m;
  m.x = x;
  precise vec4 a1 = s_mlp[w] * x.x + s_mlp[w + 1u] * x.y + s_mlp[w + 2u];
  precise vec4 h1 = 1.0 / (1.0 + exp(-a1));
  precise vec4 a2 = mat4(s_mlp[w + 3u], s_mlp[w + 4u], s_mlp[w + 5u], s_mlp[w + 6u]) * h1 + s_mlp[w + 7u];
  precise vec4 h2 = 1.0 / (1.0 + exp(-a2));
  precise vec4 z = mat4(s_mlp[w + 8u], s_mlp[w + 9u], s_mlp[w + 10u], s_mlp[w + 11u]) * h2 + s_mlp[w + 12u];
  precise vec4 s = 1.0 / (1.0 + exp(-z));
  m.h1 = h1, m.h2 = h2, m.s = s;
  return m;
}

// The MLP's depth input for slot j: t* = -(b.r) / (r^T Q r) with r = (ray, 1). A degenerate or
// overflowing quadric falls back to the centre depth z_i.
float style_depth_feature(uint j) {
  vec4 q0 = s_quadric[3u * j], q1 = s_quadric[3u * j + 1u];  // (Q00 Q01 Q02 Q11), (Q12 Q22 b0 b1)
  float b2 = s_quadric[3u * j + 2u].x, z = s_color_depth[j].w;
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

// A cheap bound on the pair's sample: it skips no pair that pair_sample() keeps. Plain: the sample
// itself. Style: the sample with opacity o + 0.5, without the MLP; dO < 0.5 and float rounding is
// monotone, so (o + 0.5) G < 1/255 implies o' G < 1/255 (and power > 0 is the same test).
PairSample pair_bound(uint j) {
  PairSample s;
  vec4 co = s_conic_opacity[j];
#if S4D_STYLE
  s.b = splat_sample(s_xy[j], vec4(co.xyz, co.w + 0.5), centre);
#else
  s.b = splat_sample(s_xy[j], co, centre);
  s.opacity = co.w;
#endif
  return s;
}

// The pair's sample. Style: the MLP on (time, depth feature), then the sample with o' = o + dO.
PairSample pair_sample(uint j) {
#if S4D_STYLE
  PairSample s;
  vec4 co = s_conic_opacity[j];
  precise vec2 x = vec2(p.time, style_depth_feature(j));
  if ((p.flags & S4D_STYLE_INPUT_SIGMOID) != 0u) x = 1.0 / (1.0 + exp(-x));
  s.m = style_mlp_fwd(j, x);
  s.drgb = 2.0 * s.m.s.rgb - 1.0;
  precise float opacity = co.w + (s.m.s.w - 0.5);
  s.opacity = opacity;
  s.b = splat_sample(s_xy[j], vec4(co.xyz, opacity), centre);
  return s;
#else
  return pair_bound(j);
#endif
}

// The colour the pair blends: c, or c + dRGB.
vec3 pair_color(uint j, PairSample s) {
#if S4D_STYLE
  return s_color_depth[j].rgb + s.drgb;
#else
  return s_color_depth[j].rgb;
#endif
}

#endif  // RASTER_PAIR_GLSL
