// One (pixel, Gaussian) evaluation with the standard guards (ALGORITHMS.md 1.5), shared by
// raster_fwd and raster_bwd so their skip decisions agree bit for bit. `precise` stops the compiler
// from contracting the two copies differently.
#ifndef SPLAT_SAMPLE_GLSL
#define SPLAT_SAMPLE_GLSL

struct SplatSample {
  bool skip;     // power > 0 or alpha < 1/255: contributes nothing
  bool clamped;  // alpha was capped at S4D_MAX_ALPHA: no gradient to conic, mean or opacity
  float alpha, G;
  vec2 d;        // mean - pixel centre
};

SplatSample splat_sample(vec2 mean, vec4 conic_opacity, vec2 pix) {
  SplatSample s;
  s.d = mean - pix;
  precise float power = -0.5 * (conic_opacity.x * s.d.x * s.d.x + conic_opacity.z * s.d.y * s.d.y) -
                        conic_opacity.y * s.d.x * s.d.y;
  s.G = exp(power);
  precise float raw = conic_opacity.w * s.G;
  s.clamped = raw > S4D_MAX_ALPHA;
  s.alpha = min(raw, S4D_MAX_ALPHA);
  s.skip = power > 0.0 || s.alpha < S4D_MIN_ALPHA;
  return s;
}

#endif  // SPLAT_SAMPLE_GLSL
