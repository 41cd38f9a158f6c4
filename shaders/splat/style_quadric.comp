// style_quadric: per Gaussian, GOF's view-space quadric (ALGORITHMS.md 4.4) for the style
// rasterizer's depth feature: Q = R_v S^-2 R_v^T with R_v = W R and S^-2 = 1/(s^2 + 1e-7), and
// b = -Q mu_v. One invocation per Gaussian; writes S4D_STYLE_QUADRIC_STRIDE floats, zeros where the
// projection culls (those Gaussians are in no tile list). Port of style_quadric in
// training/ref/include/s4d/ref/style_raster_ref.h.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "s4d_style_splat.h"
#include "flat_group.glsl"
#include "splat_project.glsl"

layout(local_size_x = S4D_SPLAT_WG) in;
layout(push_constant) uniform Push { ProjectParams p; };
layout(std430, binding = S4D_B_SQUAD_MEANS) readonly buffer Means { float means[]; };
layout(std430, binding = S4D_B_SQUAD_LOG_SCALES) readonly buffer LogScales { float log_scales[]; };
layout(std430, binding = S4D_B_SQUAD_QUATS) readonly buffer Quats { float quats[]; };
layout(std430, binding = S4D_B_SQUAD_QUADRIC) writeonly buffer Quadric { vec4 quadric[]; };  // [N*3] vec4

void main() {
  uint i = flat_group_id() * S4D_SPLAT_WG + gl_LocalInvocationIndex;
  if (i >= p.n) return;
  vec3 mu = vec3(means[3 * i], means[3 * i + 1], means[3 * i + 2]);
  vec3 ls = vec3(log_scales[3 * i], log_scales[3 * i + 1], log_scales[3 * i + 2]);
  vec4 rq = vec4(quats[4 * i], quats[4 * i + 1], quats[4 * i + 2], quats[4 * i + 3]);
  SplatProjection pr = splat_project_one(p.cam, mu, ls, rq);
  if (!pr.visible) {
    quadric[3 * i] = vec4(0.0), quadric[3 * i + 1] = vec4(0.0), quadric[3 * i + 2] = vec4(0.0);
    return;
  }
  mat3 Rv;  // Rv[c][r]: GLSL matrices are column-major
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      Rv[c][r] = pr.W[3 * r] * pr.R[c] + pr.W[3 * r + 1] * pr.R[3 + c] + pr.W[3 * r + 2] * pr.R[6 + c];
  vec3 inv_s2 = 1.0 / (pr.s * pr.s + S4D_STYLE_SCALE_EPS);
  mat3 Q = Rv * mat3(inv_s2.x, 0.0, 0.0, 0.0, inv_s2.y, 0.0, 0.0, 0.0, inv_s2.z) * transpose(Rv);
  vec3 b = -(Q * pr.t);
  quadric[3 * i] = vec4(Q[0][0], Q[1][0], Q[2][0], Q[1][1]);
  quadric[3 * i + 1] = vec4(Q[2][1], Q[2][2], b.x, b.y);
  quadric[3 * i + 2] = vec4(b.z, 0.0, 0.0, 0.0);
}
