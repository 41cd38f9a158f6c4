// One pixel's front-to-back blend state and step (ALGORITHMS.md 1.5), shared by both variants of
// raster_fwd and by the blend_ceiling benchmark, so the benchmark measures exactly the production
// loop. The includer declares s_xy, s_conic_opacity and s_color_depth (shared batch arrays) first.
#ifndef SPLAT_BLEND_GLSL
#define SPLAT_BLEND_GLSL
#include "raster_pair.glsl"

bool done;
float T = 1.0, depth = 0.0;
vec3 color = vec3(0.0);
uint count = 0u, last = 0u;

// Blends entry j of the batch whose first entry is list position `position0`.
void blend(uint j, uint batch, uint position0) {
  if (done || j >= batch) return;
  PairSample s = pair_bound(j);
  if (s.b.skip) return;
  pair_finish(j, s);
  if (s.b.skip) return;
  float next = T * (1.0 - s.b.alpha);
  if (next < S4D_MIN_TRANSMITTANCE) {
    done = true;  // this Gaussian is not added, as in graphdeco
    return;
  }
  vec4 cd = s_color_depth[j];
  color += pair_color(j, s) * (s.b.alpha * T);
  depth += cd.w * (s.b.alpha * T);
  T = next;
  ++count;
  last = position0 + j + 1u;
}

// Blends a loaded batch, S4D_RASTER_UNROLL entries per loop iteration written out without a loop
// (llvmpipe's loop-iteration cap, see s4d_splat.h and s4d_style_splat.h).
void blend_batch(uint batch, uint position0) {
  for (uint j = 0u; !done && j < batch; j += S4D_RASTER_UNROLL) {
    blend(j, batch, position0), blend(j + 1u, batch, position0);
    blend(j + 2u, batch, position0), blend(j + 3u, batch, position0);
#if S4D_RASTER_UNROLL == 8
    blend(j + 4u, batch, position0), blend(j + 5u, batch, position0);
    blend(j + 6u, batch, position0), blend(j + 7u, batch, position0);
#endif
  }
}

#endif  // SPLAT_BLEND_GLSL
