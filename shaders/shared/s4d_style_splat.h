// Shared layouts of the style rasterizer ("Style Gaussians", ALGORITHMS.md 4.3-4.4): the tile
// rasterizer of s4d_splat.h with a tiny per-Gaussian MLP evaluated per (pixel, Gaussian) pair inside
// the blend loop. Its CPU twin is training/ref/include/s4d/ref/style_raster_ref.h.
#ifndef S4D_STYLE_SPLAT_H
#define S4D_STYLE_SPLAT_H
#include "s4d_splat.h"

// Per-Gaussian MLP 2 -> 4 -> 4 -> 4 (sigmoid hidden layers), S4D_STYLE_MLP_STRIDE floats per Gaussian
// in SuperGaussians' order. Matrices are column-major: W[r][c] is at offset + 4 c + r.
#define S4D_STYLE_MLP_W1 0        // 4x2, input (time, depth feature) -> hidden 1
#define S4D_STYLE_MLP_B1 8
#define S4D_STYLE_MLP_W2 12       // 4x4
#define S4D_STYLE_MLP_B2 28
#define S4D_STYLE_MLP_W3 32       // 4x4, hidden 2 -> (dR, dG, dB, dO) pre-activations
#define S4D_STYLE_MLP_B3 48
#define S4D_STYLE_MLP_STRIDE 52
#define S4D_STYLE_MLP_VEC4S 13    // every block starts on a vec4 boundary, so kernels read 13 vec4s

// Per-Gaussian view-space quadric of GOF's ray-Gaussian depth (4.4), S4D_STYLE_QUADRIC_STRIDE floats:
// Q = R_v S^-2 R_v^T (upper triangle 00, 01, 02, 11, 12, 22), b = -Q mu_v, then padding so a
// Gaussian is three vec4s. The depth of maximum response along the ray t r is t* = -(b.r) / (r^T Q r).
#define S4D_STYLE_QUADRIC_Q 0
#define S4D_STYLE_QUADRIC_B 6
#define S4D_STYLE_QUADRIC_STRIDE 12
#define S4D_STYLE_SCALE_EPS 1e-7  // S^-2 = 1 / (s^2 + 1e-7) as in GOF: flat Gaussians keep a finite Q

// The depth feature x1 of t* (RasterParams.depth_mode).
#define S4D_STYLE_DEPTH_NDC 0u       // far/(far - near) (1 - near/t*), t* clamped to [near, far]: in [0, 1]
#define S4D_STYLE_DEPTH_RELATIVE 1u  // (t* - z_i) * depth_scale, z_i the Gaussian's camera-space depth
#define S4D_STYLE_NDC_NEAR 0.2       // 2DGS/GOF's planes
#define S4D_STYLE_NDC_FAR 100.0

// RasterParams.flags: S4D_RASTER_HAS_V_ALPHA and S4D_RASTER_HAS_V_DEPTH (backward) plus:
#define S4D_STYLE_INPUT_SIGMOID 4u  // x = sigmoid(x) before layer 1 (SuperGaussians does)

// A batch slot's style parts in shared memory (raster_batch.glsl): 13 MLP vec4s, then the quadric's
// 3 vec4s.
#define S4D_STYLE_SLOT_PARTS 16
#define S4D_STYLE_SLOT_QUADRIC S4D_STYLE_MLP_VEC4S

// List entries per shared-memory batch. A batch holds the 16 style parts and the plain
// rasterizer's 10 floats (+ id) per entry: 64 entries take 19 KiB of lavapipe's 32 KiB.
#define S4D_STYLE_BATCH 64
// The style kernels walk a batch in two loops (raster_walk.glsl): S4D_STYLE_MARK_UNROLL slots per
// iteration test the cheap bound, then S4D_STYLE_UNROLL marked slots per iteration run the MLP, both
// written out (the plain rasterizer's S4D_BLEND_UNROLL pattern, s4d_splat.h). Each visit inlines the
// MLP (and its backward and 62 atomics), so 4 rather than 8: on lavapipe the kernels then compile in
// ~9 s instead of ~22 s cold (Mesa caches them). llvmpipe counts a loop's final, exiting condition
// check as an iteration too, so a batch costs at most 1 + (64 / 8 + 1) + (64 / 4 + 1) = 27 of its
// 65535 and 2427 batches = 155,328 entries fit. The compare-and-swap backward adds one loop per
// atomic, 62 per entry (52 weights + 10 grad2d): 27 + 64 * 62 per batch, 16 batches = 1024 entries,
// kept at 900 for ~9,000 iterations of contended retries.
#define S4D_STYLE_UNROLL 4
#define S4D_STYLE_MARK_UNROLL 8
#define S4D_LLVMPIPE_MAX_STYLE_LIST 155000u
#define S4D_LLVMPIPE_MAX_STYLE_LIST_CAS 900u

// Binding ids of style_quadric.
#define S4D_B_SQUAD_MEANS 0         // [N*3]
#define S4D_B_SQUAD_LOG_SCALES 1    // [N*3]
#define S4D_B_SQUAD_QUATS 2         // [N*4]
#define S4D_B_SQUAD_QUADRIC 3       // [N*S4D_STYLE_QUADRIC_STRIDE]; zeros for culled Gaussians

// The style variants of raster_fwd and raster_bwd take the plain bindings (s4d_splat.h) plus:
#define S4D_B_RASTER_QUADRIC 11     // [N*S4D_STYLE_QUADRIC_STRIDE]
#define S4D_B_RASTER_STYLE_MLP 12   // [N*S4D_STYLE_MLP_STRIDE]
#define S4D_B_RBWD_QUADRIC S4D_B_RASTER_QUADRIC
#define S4D_B_RBWD_STYLE_MLP S4D_B_RASTER_STYLE_MLP
#define S4D_B_RBWD_V_STYLE_MLP 13   // [N*S4D_STYLE_MLP_STRIDE], accumulated (zero it first)

#endif  // S4D_STYLE_SPLAT_H
