// Shared layouts and constants of the tile-sorted Gaussian rasterizer (ALGORITHMS.md 1). The CPU
// twin (training/ref/include/s4d/ref/splat_project_ref.h) takes its constants from here too.
#ifndef S4D_SPLAT_H
#define S4D_SPLAT_H
#include "s4d_common.h"

// Constants (graphdeco config.h / auxiliary.h values). Plain literals: float in GLSL, double in C++.
#define S4D_TILE_SIZE 16                 // 16x16 pixel tiles: one workgroup per tile, one invocation per pixel
#define S4D_TILE_PIXELS 256              // S4D_TILE_SIZE^2: also the blend batch size
#define S4D_NEAR_Z 0.2                   // cull at camera z <= 0.2: keeps 1/z and the Jacobian bounded
#define S4D_GUARD_BAND 1.3               // clamp x/z, y/z to 1.3 tan(fov/2): off-screen Jacobians stay sane
#define S4D_DILATION 0.3                 // low-pass filter on the 2D covariance: a splat covers ~1 pixel
#define S4D_SIGMA_EXTENT 3.0             // radius = 3 sigma of the larger eigenvalue
#define S4D_MIN_EIGEN_GAP 0.1            // sqrt(max(0.1, mid^2 - det)) in graphdeco's eigenvalue formula
#define S4D_MAX_ALPHA 0.99               // alpha cap: T never reaches 0, 1/(1 - alpha) stays bounded
#define S4D_MIN_ALPHA (1.0 / 255.0)      // contributions below one 8-bit step are skipped
#define S4D_MIN_TRANSMITTANCE 0.0001     // stop blending once the pixel is practically opaque
#define S4D_MAX_SH_DEGREE 3
#define S4D_MAX_SH_COEFFS 16

#define S4D_SPLAT_WG 256                 // per-Gaussian and per-instance kernels
// The blend loops visit S4D_BLEND_UNROLL list entries per loop iteration, written out without a
// loop. llvmpipe (lavapipe) stops any invocation after 65535 loop iterations in total, counting each
// loop's final, exiting condition check too, so this sets the longest tile list it renders
// correctly: 65534 / (1 + (256 / 8 + 1)) = 1927 batches of 256 = 493,312 entries
// (S4D_LLVMPIPE_MAX_TILE_LIST; measured: 490,000 render whole, 496,000 lose the end); the host
// checks it. The compare-and-swap gradient path loops once per atomic (10 per list entry):
// 65534 / (34 + 2560) = 25 batches, 6400 entries; S4D_LLVMPIPE_MAX_TILE_LIST_CAS keeps a margin.
#define S4D_BLEND_UNROLL 8
#define S4D_LLVMPIPE_MAX_TILE_LIST 493000u
#define S4D_LLVMPIPE_MAX_TILE_LIST_CAS 5000u  // 1,300 iterations of headroom for contended retries
#define S4D_CULLED_DEPTH_KEY 0xFFFFFFFFu // depth sort key of a culled Gaussian: sorts after every visible one

// Per-Gaussian cotangents accumulated by raster_bwd ("grad2d"), S4D_G2D_STRIDE floats per Gaussian.
#define S4D_G2D_XY 0        // dL/d(u, v), pixels (graphdeco's NDC gradient is this times (W/2, H/2))
#define S4D_G2D_CONIC 2     // dL/d(A, B, C) of the conic (A, B; B, C); B's is the full derivative
#define S4D_G2D_OPACITY 5   // dL/d sigmoid(opacity logit)
#define S4D_G2D_RGB 6       // dL/d rgb
#define S4D_G2D_DEPTH 9     // dL/d camera-space depth (through the depth output)
#define S4D_G2D_STRIDE 10

// Bit flags of ProjectParams.flags and RasterParams.flags.
#define S4D_SPLAT_USE_COLORS 1u   // colour from the per-Gaussian colour buffer instead of SH
#define S4D_RASTER_HAS_V_ALPHA 1u // raster_bwd: the alpha cotangent buffer is bound
#define S4D_RASTER_HAS_V_DEPTH 2u // raster_bwd: the depth cotangent buffer is bound

// Binding ids. Per-Gaussian arrays are flat floats: means/log_scales/colors [N*3], quats [N*4] (w,x,y,z),
// opacity_logits [N], sh [N*K*3] coefficient-major.
// Floats per Gaussian of those arrays; the host's attribute table (s4d/splat/gaussian_buffers.h) is
// built from these. sh holds K coefficients of 3 channels each.
#define S4D_MEANS_FLOATS 3
#define S4D_LOG_SCALES_FLOATS 3
#define S4D_QUATS_FLOATS 4
#define S4D_OPACITY_LOGITS_FLOATS 1
#define S4D_SH_FLOATS_PER_COEFF 3
#define S4D_COLORS_FLOATS 3
#define S4D_B_PROJ_MEANS 0
#define S4D_B_PROJ_LOG_SCALES 1
#define S4D_B_PROJ_QUATS 2
#define S4D_B_PROJ_OPACITY_LOGITS 3
#define S4D_B_PROJ_SH 4
#define S4D_B_PROJ_COLORS 5
#define S4D_B_PROJ_XY 6             // [N] vec2 projected mean, pixels
#define S4D_B_PROJ_CONIC_OPACITY 7  // [N] vec4 (A, B, C, opacity)
#define S4D_B_PROJ_COLOR_DEPTH 8    // [N] vec4 (r, g, b, camera z)
#define S4D_B_PROJ_INFO 9           // [N] uvec4 (x_min | y_min << 16, x_max | y_max << 16, radius, clamped rgb bits); max exclusive
#define S4D_B_PROJ_DEPTH_KEYS 10    // [N] u32 depth bits, S4D_CULLED_DEPTH_KEY when culled
#define S4D_B_PROJ_TILES_TOUCHED 11 // [N] u32 tile-rectangle area, 0 when culled

#define S4D_B_COUNT_SORTED_IDS 0    // [N] Gaussian ids in depth order
#define S4D_B_COUNT_TILES_TOUCHED 1 // [N]
#define S4D_B_COUNT_OFFSETS 2       // [N + 1] tiles touched in depth order; scanned afterwards
#define S4D_B_COUNT_TOTALS 3        // [3] u32: instances (low word, carries), largest tiles_touched; zero first

#define S4D_B_EMIT_SORTED_IDS 0     // [N]
#define S4D_B_EMIT_OFFSETS 1        // [N + 1] exclusive scan of the counts; [N] is the instance count
#define S4D_B_EMIT_INFO 2           // [N] uvec4
#define S4D_B_EMIT_TILE_KEYS 3      // [instances] tile id
#define S4D_B_EMIT_GAUSSIAN_IDS 4   // [instances] Gaussian id

#define S4D_B_RANGES_TILE_KEYS 0    // [instances] tile ids, sorted
#define S4D_B_RANGES_OUT 1          // [tiles] uvec2 (begin, end) into the sorted instances
#define S4D_B_RANGES_LIVE 2         // InstanceArgs: its first word is the live instance count

#define S4D_B_ARGS_OFFSETS 0        // [N + 1] scanned; [N] is the instance count (mod 2^32)
#define S4D_B_ARGS_OUT 1            // InstanceArgs

#define S4D_B_LIST_STATS_RANGES 0   // [tiles] uvec2
#define S4D_B_LIST_STATS_OUT 1      // [1] u32 longest tile list (atomic max; zero it first)

#define S4D_B_RASTER_RANGES 0
#define S4D_B_RASTER_GAUSSIAN_IDS 1
#define S4D_B_RASTER_XY 2
#define S4D_B_RASTER_CONIC_OPACITY 3
#define S4D_B_RASTER_COLOR_DEPTH 4
#define S4D_B_RASTER_RGB 5          // [H*W*3] blended colour + T_final * background
#define S4D_B_RASTER_ALPHA 6        // [H*W] 1 - T_final
#define S4D_B_RASTER_DEPTH 7        // [H*W] sum of depth_i alpha_i T_i (not normalised by alpha)
#define S4D_B_RASTER_COUNT 8        // [H*W] u32 Gaussians blended
#define S4D_B_RASTER_LAST 9         // [H*W] u32 1 + tile-list position of the last blended Gaussian
#define S4D_B_RASTER_FINAL_T 10     // [H*W] T_final, kept exact for the backward (1 - alpha loses it)

// raster_bwd reads raster_fwd's inputs at the same bindings (raster_batch.glsl declares them once).
#define S4D_B_RBWD_RANGES S4D_B_RASTER_RANGES
#define S4D_B_RBWD_GAUSSIAN_IDS S4D_B_RASTER_GAUSSIAN_IDS
#define S4D_B_RBWD_XY S4D_B_RASTER_XY
#define S4D_B_RBWD_CONIC_OPACITY S4D_B_RASTER_CONIC_OPACITY
#define S4D_B_RBWD_COLOR_DEPTH S4D_B_RASTER_COLOR_DEPTH
#define S4D_B_RBWD_FINAL_T 5
#define S4D_B_RBWD_LAST 6
#define S4D_B_RBWD_V_RGB 7          // [H*W*3]
#define S4D_B_RBWD_V_ALPHA 8        // [H*W], read only with S4D_RASTER_HAS_V_ALPHA
#define S4D_B_RBWD_V_DEPTH 9        // [H*W], read only with S4D_RASTER_HAS_V_DEPTH
#define S4D_B_RBWD_GRAD2D 10        // [N*S4D_G2D_STRIDE], accumulated with atomics (zero it first)
// raster_bwd: pixels per invocation (a column of the tile), so S4D_RBWD_INVOCATIONS a workgroup.
// Two variants (variants.cmake): 8 for CPU devices, where every subgroup reduction and atomic is a
// loop over the lanes (lavapipe: the 8-pixel kernel's backward is 0.11-0.26x the 1-pixel one's), and
// 1 for GPUs, where those are parallel in hardware and the 8-pixel kernel's 32-invocation workgroups
// and 8 pixels of state cost occupancy (NVIDIA H200: 2.5x slower plain, 5.7x slower style).
#define S4D_RBWD_PIXELS_CPU 8
#define S4D_RBWD_PIXELS_GPU 1
#ifndef S4D_RBWD_PIXELS
#define S4D_RBWD_PIXELS S4D_RBWD_PIXELS_CPU
#endif
#define S4D_RBWD_INVOCATIONS (S4D_TILE_PIXELS / S4D_RBWD_PIXELS)
// raster_fwd: pixels per invocation, the same split (variants.cmake): on llvmpipe every
// shared-memory load is a loop over the lanes, so a slot loaded once for 8 pixels costs an eighth.
#define S4D_RFWD_PIXELS_CPU 8
#define S4D_RFWD_PIXELS_GPU 1
#ifndef S4D_RFWD_PIXELS
#define S4D_RFWD_PIXELS S4D_RFWD_PIXELS_CPU
#endif
#define S4D_RFWD_INVOCATIONS (S4D_TILE_PIXELS / S4D_RFWD_PIXELS)
// Specialization constant of raster_bwd: the smallest number of lanes a subgroup of it can have,
// min(device's smallest subgroup size, the variant's S4D_RBWD_INVOCATIONS, 32), which fixes how many rounds of
// lane-parallel atomics each pair's cotangents take (ceil(values / lanes)).
#define S4D_RBWD_SPEC_MIN_SUBGROUP 0

#define S4D_B_PBWD_MEANS 0
#define S4D_B_PBWD_LOG_SCALES 1
#define S4D_B_PBWD_QUATS 2
#define S4D_B_PBWD_OPACITY_LOGITS 3
#define S4D_B_PBWD_SH 4
#define S4D_B_PBWD_COLORS 5
#define S4D_B_PBWD_INFO 6
#define S4D_B_PBWD_CONIC_OPACITY 7
#define S4D_B_PBWD_GRAD2D 8
#define S4D_B_PBWD_V_MEANS 9        // outputs are assigned, not accumulated; culled Gaussians get 0
#define S4D_B_PBWD_V_LOG_SCALES 10
#define S4D_B_PBWD_V_QUATS 11
#define S4D_B_PBWD_V_OPACITY_LOGITS 12
#define S4D_B_PBWD_V_SH 13
#define S4D_B_PBWD_V_COLORS 14

S4D_NAMESPACE_BEGIN

// A pinhole camera: world_to_cam rows (OpenCV axes: x right, y down, z forward), pixel (i, j)
// centred at (i + 0.5, j + 0.5), u = fx x/z + cx.
struct SplatCamera {
  vec4 view_row0;   // (R00, R01, R02, t0)
  vec4 view_row1;
  vec4 view_row2;
  vec4 intrinsics;  // (fx, fy, cx, cy)
  uvec4 size;       // (width, height, tiles_x, tiles_y)
};

// Push constants of project_fwd and project_bwd.
struct ProjectParams {
  SplatCamera cam;
  uint n;          // Gaussians
  uint sh_degree;  // active degree 0..3
  uint sh_coeffs;  // K: coefficients stored per Gaussian and channel, >= (sh_degree + 1)^2
  uint flags;      // S4D_SPLAT_USE_COLORS
};

// Push constants of count_tiles, emit_instances and tile_ranges.
struct BinningParams {
  uint n;          // Gaussians (count_tiles, emit_instances) or the instance capacity (tile_ranges)
  uint tiles_x;
  uint capacity;   // emit_instances: instances it may write; those past it are dropped
  uint _pad1;
};

// Push constants of instance_args.
struct InstanceArgsParams {
  uint n;             // Gaussians: offsets[n] holds the instance count
  uint capacity;      // instances the buffers hold
  uint max_groups_x;  // the device's 1-D workgroup limit; larger dispatches split into 2-D rows
  uint _pad0;
};

// Written by instance_args on the device, so one submission renders a frame without the host
// reading the instance count first: the live count and the indirect dispatches over it
// (VkDispatchIndirectCommand x, y, z; the fourth word pads to 16 bytes).
struct InstanceArgs {
  uint live;  // min(instances, capacity): what emit_instances wrote and the sort and tile_ranges read
  uint _pad0;
  uint _pad1;
  uint _pad2;
  uvec4 ranges_groups;  // tile_ranges: ceil(live / S4D_SPLAT_WG) workgroups
  uvec4 sort_groups;    // radix sort blocks: ceil(live / S4D_RADIX_BLOCK) workgroups
};
#define S4D_INSTANCE_ARGS_RANGES_OFFSET 16  // bytes, InstanceArgs::ranges_groups
#define S4D_INSTANCE_ARGS_SORT_OFFSET 32    // bytes, InstanceArgs::sort_groups

// Push constants of raster_fwd and raster_bwd, plain and style variants. The last four fields
// and `intrinsics` drive the style variants only (s4d_style_splat.h).
struct RasterParams {
  uvec4 size;         // (width, height, tiles_x, tiles_y)
  vec4 background;    // (r, g, b, unused)
  vec4 intrinsics;    // (fx, fy, cx, cy): pixel (i, j) looks along ((i + 0.5 - cx)/fx, (j + 0.5 - cy)/fy, 1)
  uint flags;         // S4D_RASTER_HAS_V_ALPHA | S4D_RASTER_HAS_V_DEPTH (raster_bwd) | S4D_STYLE_INPUT_SIGMOID
  uint depth_mode;    // S4D_STYLE_DEPTH_NDC or S4D_STYLE_DEPTH_RELATIVE
  float time;         // style MLP input x0, normalised time in [0, 1)
  float depth_scale;  // S4D_STYLE_DEPTH_RELATIVE: world units -> feature units
};

S4D_NAMESPACE_END

#endif  // S4D_SPLAT_H
