// One pixel's front-to-back blend state and step (ALGORITHMS.md 1.5), shared by both variants of
// raster_fwd and by the blend_ceiling benchmark, so the benchmark measures exactly the production
// loop. The includer declares s_xy, s_conic_opacity and s_color_depth (shared batch arrays) first.
// An invocation blends S4D_RFWD_PIXELS pixels (a column; 1 unless the includer sets 8): the pixel
// being blended lives in the globals below, the others in `rfwd_px`, swapped in and out around each
// step, so every slot is loaded from shared memory once for all of them (raster_pair.glsl's Slot).
#ifndef SPLAT_BLEND_GLSL
#define SPLAT_BLEND_GLSL
#include "raster_pair.glsl"

bool done;
float T = 1.0, depth = 0.0;
vec3 color = vec3(0.0);
uint count = 0u, last = 0u;

#ifndef S4D_RFWD_PIXELS
#define S4D_RFWD_PIXELS 1
#endif
#if S4D_RFWD_PIXELS == 1
#define RFWD_EACH(F) F(0)
#define RFWD_IN(k)
#define RFWD_OUT(k)
bool invocation_done() { return done; }
#elif S4D_RFWD_PIXELS == 8
#define RFWD_EACH(F) F(0) F(1) F(2) F(3) F(4) F(5) F(6) F(7)
struct BlendPixel {
  vec2 centre, ray;
  bool done;
  float T, depth;
  vec3 color;
  uint count, last;
};
BlendPixel rfwd_px[S4D_RFWD_PIXELS];
#if S4D_STYLE
#define RFWD_IN_RAY(k) ray = rfwd_px[k].ray;
#else
#define RFWD_IN_RAY(k)
#endif
#define RFWD_IN(k) centre = rfwd_px[k].centre, done = rfwd_px[k].done, T = rfwd_px[k].T, depth = rfwd_px[k].depth; \
  color = rfwd_px[k].color, count = rfwd_px[k].count, last = rfwd_px[k].last; RFWD_IN_RAY(k)
#define RFWD_OUT(k) rfwd_px[k].done = done, rfwd_px[k].T = T, rfwd_px[k].depth = depth, rfwd_px[k].color = color; \
  rfwd_px[k].count = count, rfwd_px[k].last = last;
bool invocation_done() {
  return rfwd_px[0].done && rfwd_px[1].done && rfwd_px[2].done && rfwd_px[3].done && rfwd_px[4].done &&
         rfwd_px[5].done && rfwd_px[6].done && rfwd_px[7].done;
}
#else
#error "S4D_RFWD_PIXELS is 1 or 8"
#endif

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

// Blends slot j (data sl) into each of the invocation's pixels.
#define RFWD_BLEND(k) RFWD_IN(k) blend_slot(sl, j, position0); RFWD_OUT(k)

#if S4D_STYLE
#include "raster_walk.glsl"

// Marks slot j in `bits` when one of this invocation's pixels still blends and may meet it.
void blend_mark(uint j, uint batch, inout uvec2 bits) {
  if (j >= batch) return;  // uniform: every invocation has the same batch
  Slot sb = slot_load_bound(j);
  bool needed = false;
#define RFWD_MARK(k) RFWD_IN(k) needed = needed || (!done && !pair_bound(sb).b.skip);
  RFWD_EACH(RFWD_MARK)
  raster_walk_mark(bits, j, needed);
}

// Blends the next marked slot, if any, and unmarks it.
void blend_next(inout uvec2 todo, uint position0) {
  if (todo == uvec2(0u) || invocation_done()) return;
  uint j = raster_walk_pop(todo);
  Slot sl = slot_load(j);
  RFWD_EACH(RFWD_BLEND)
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
  while (!invocation_done() && todo != uvec2(0u)) {
    blend_next(todo, position0), blend_next(todo, position0);
    blend_next(todo, position0), blend_next(todo, position0);
  }
}
#else
// Blends entry j if there is one.
void blend(uint j, uint batch, uint position0) {
  if (invocation_done() || j >= batch) return;
  Slot sl = slot_load(j);
  RFWD_EACH(RFWD_BLEND)
}

// Blends a loaded batch, S4D_RASTER_UNROLL entries per loop iteration written out without a loop
// (llvmpipe's loop-iteration cap, see s4d_splat.h).
void blend_batch(uint batch, uint position0) {
  for (uint j = 0u; !invocation_done() && j < batch; j += S4D_RASTER_UNROLL) {
    blend(j, batch, position0), blend(j + 1u, batch, position0);
    blend(j + 2u, batch, position0), blend(j + 3u, batch, position0);
    blend(j + 4u, batch, position0), blend(j + 5u, batch, position0);
    blend(j + 6u, batch, position0), blend(j + 7u, batch, position0);
  }
}
#endif

#endif  // SPLAT_BLEND_GLSL
