// The variant switch of the rasterizer family: S4D_STYLE (from the variant table in
// shaders/variants.cmake) picks the plain kernels (0) or the Style Gaussians ones (1), which run each
// Gaussian's MLP per (pixel, Gaussian) pair (ALGORITHMS.md 4.3). It fixes the shared-memory batch
// and the blend loops' unrolling; raster_pair.glsl holds the per-pair sampling and colour.
#ifndef RASTER_VARIANT_GLSL
#define RASTER_VARIANT_GLSL
#include "s4d_style_splat.h"
#if !defined(S4D_STYLE) || (S4D_STYLE != 0 && S4D_STYLE != 1)
#error "S4D_STYLE must be 0 (plain) or 1 (style): set it in the variant table"
#endif

#if S4D_STYLE
#define S4D_RASTER_BATCH S4D_STYLE_BATCH
#define S4D_RASTER_UNROLL S4D_STYLE_UNROLL
#define S4D_RASTER_MARK_UNROLL S4D_STYLE_MARK_UNROLL
#if S4D_RASTER_MARK_UNROLL != 8
#error "the marking loops call their step 8 times per iteration"
#endif
#else
#define S4D_RASTER_BATCH S4D_TILE_PIXELS
#define S4D_RASTER_UNROLL S4D_BLEND_UNROLL
#endif
#if (S4D_STYLE && S4D_RASTER_UNROLL != 4) || (!S4D_STYLE && S4D_RASTER_UNROLL != 8)
#error "the blend loops call their step 4 (style) or 8 (plain) times per iteration"
#endif

#endif  // RASTER_VARIANT_GLSL
