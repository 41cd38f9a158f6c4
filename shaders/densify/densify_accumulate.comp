// densify_accumulate: densification statistics from one rendered view (ALGORITHMS.md 2.2, 3.3).
// One thread per Gaussian; Gaussians with radius 0 (culled in that view) are left alone.
//   S4D_ACCUM_VIEW (graphdeco):   accum += |grad2d_xy * (W/2, H/2)|, count += 1,
//                                 max_radius = max(max_radius, radius).
//   S4D_ACCUM_BATCH_ADD:          scratch.xy += grad2d_xy * (W/2, H/2), scratch.r = max(scratch.r, radius).
//   S4D_ACCUM_BATCH_END (4DGaussians, once per batch, for Gaussians seen in any view of it):
//                                 accum += |scratch.xy|, count += 1, max_radius = max(max_radius,
//                                 scratch.r); the scratch is zeroed for the next batch.
// Buffers a mode does not use are bound to anything (see s4d_densify.h).
#version 450
#extension GL_GOOGLE_include_directive : require
#include "s4d_densify.h"
#include "s4d_splat.h"
#include "flat_group.glsl"

layout(local_size_x = S4D_DENSIFY_WG) in;
layout(push_constant) uniform Push { AccumulateParams p; };
layout(std430, binding = S4D_B_ACCUM_GRAD2D) readonly buffer Grad2d { float grad2d[]; };  // [N*S4D_G2D_STRIDE]
layout(std430, binding = S4D_B_ACCUM_INFO) readonly buffer Info { uvec4 info[]; };        // [N]
layout(std430, binding = S4D_B_ACCUM_GRAD_ACCUM) buffer Accum { float grad_accum[]; };    // [N]
layout(std430, binding = S4D_B_ACCUM_GRAD_COUNT) buffer Count { float grad_count[]; };    // [N]
layout(std430, binding = S4D_B_ACCUM_MAX_RADIUS) buffer Radius { float max_radius[]; };   // [N]
layout(std430, binding = S4D_B_ACCUM_SCRATCH) buffer Scratch { float scratch[]; };        // [N*3]

void main() {
  uint i = flat_group_id() * S4D_DENSIFY_WG + gl_LocalInvocationIndex;
  if (i >= p.n) return;
  if (p.mode == S4D_ACCUM_BATCH_END) {
    uint s = i * S4D_ACCUM_SCRATCH_STRIDE;
    float r = scratch[s + 2];
    if (r > 0.0) {
      grad_accum[i] += length(vec2(scratch[s], scratch[s + 1]));
      grad_count[i] += 1.0;
      max_radius[i] = max(max_radius[i], r);
    }
    scratch[s] = 0.0;
    scratch[s + 1] = 0.0;
    scratch[s + 2] = 0.0;
    return;
  }
  uint radius = info[i].z;
  if (radius == 0u) return;
  uint g = i * S4D_G2D_STRIDE + S4D_G2D_XY;
  // Products first, as the twin does; `precise` keeps the compiler from fusing them into the sums.
  precise float gx = grad2d[g] * p.half_width;
  precise float gy = grad2d[g + 1] * p.half_height;
  if (p.mode == S4D_ACCUM_VIEW) {
    grad_accum[i] += length(vec2(gx, gy));
    grad_count[i] += 1.0;
    max_radius[i] = max(max_radius[i], float(radius));
  } else {
    uint s = i * S4D_ACCUM_SCRATCH_STRIDE;
    scratch[s] += gx;
    scratch[s + 1] += gy;
    scratch[s + 2] = max(scratch[s + 2], float(radius));
  }
}
