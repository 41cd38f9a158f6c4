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

// Blends the pair with slot j (data sl) of the batch whose first entry is list position `position0`.
void blend_slot(Slot sl, uint j, uint position0) {
  if (done) return;
  PairSample s = pair_sample(sl);
  if (s.b.skip) return;
  float next = T * (1.0 - s.b.alpha);
  if (next < S4D_MIN_TRANSMITTANCE) {
    done = true;  // this Gaussian is not added, as in graphdeco
    return;
  }
  color += pair_color(sl, s) * (s.b.alpha * T);
  depth += sl.color_depth.w * (s.b.alpha * T);
  T = next;
  ++count;
  last = position0 + j + 1u;
}

#if S4D_STYLE
#include "raster_walk.glsl"

// Marks slot j in `bits` when this pixel still blends and may meet it.
void blend_mark(uint j, uint batch, inout uvec2 bits) {
  if (j >= batch) return;  // uniform: every invocation has the same batch
  raster_walk_mark(bits, j, !done && !pair_bound(slot_load_bound(j)).b.skip);
}

// Blends the next marked slot, if any, and unmarks it.
void blend_next(inout uvec2 todo, uint position0) {
  if (todo == uvec2(0u) || done) return;
  uint j = raster_walk_pop(todo);
  blend_slot(slot_load(j), j, position0);
}

// Blends a loaded batch in two passes (raster_walk.glsl): which slots meet a pixel of this subgroup
// (the cheap bound, S4D_RASTER_MARK_UNROLL per iteration, then one subgroupOr), then only those, in
// list order, S4D_RASTER_UNROLL per iteration. Loops only, written out (llvmpipe's loop-iteration
// cap, see s4d_style_splat.h).
void blend_batch(uint batch, uint position0) {
  uvec2 bits = uvec2(0u);
  for (uint j = 0u; j < batch; j += S4D_RASTER_MARK_UNROLL) {
    blend_mark(j, batch, bits), blend_mark(j + 1u, batch, bits), blend_mark(j + 2u, batch, bits);
    blend_mark(j + 3u, batch, bits), blend_mark(j + 4u, batch, bits), blend_mark(j + 5u, batch, bits);
    blend_mark(j + 6u, batch, bits), blend_mark(j + 7u, batch, bits);
  }
  uvec2 todo = raster_walk_todo(bits);
  while (!done && todo != uvec2(0u)) {
    blend_next(todo, position0), blend_next(todo, position0);
    blend_next(todo, position0), blend_next(todo, position0);
  }
}
#else
// Blends entry j if there is one.
void blend(uint j, uint batch, uint position0) {
  if (done || j >= batch) return;
  blend_slot(slot_load(j), j, position0);
}

// Blends a loaded batch, S4D_RASTER_UNROLL entries per loop iteration written out without a loop
// (llvmpipe's loop-iteration cap, see s4d_splat.h).
void blend_batch(uint batch, uint position0) {
  for (uint j = 0u; !done && j < batch; j += S4D_RASTER_UNROLL) {
    blend(j, batch, position0), blend(j + 1u, batch, position0);
    blend(j + 2u, batch, position0), blend(j + 3u, batch, position0);
    blend(j + 4u, batch, position0), blend(j + 5u, batch, position0);
    blend(j + 6u, batch, position0), blend(j + 7u, batch, position0);
  }
}
#endif

#endif  // SPLAT_BLEND_GLSL
