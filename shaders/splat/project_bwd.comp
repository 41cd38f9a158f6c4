// project_bwd: per Gaussian, from the accumulated screen-space cotangents (grad2d) to the raw
// parameters: opacity logit, SH coefficients (or colours), mean (through the view direction, the
// projection and the EWA Jacobian), covariance -> log-scales and quaternion (with the normalisation
// Jacobian). GLSL port of project_bwd in training/ref/include/s4d/ref/splat_project_ref.h; outputs
// are assigned, and culled Gaussians get zeros.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "s4d_splat.h"
#include "flat_group.glsl"
#include "splat_project.glsl"
#include "splat_sh.glsl"

layout(local_size_x = S4D_SPLAT_WG) in;
layout(push_constant) uniform Push { ProjectParams p; };
layout(std430, binding = S4D_B_PBWD_MEANS) readonly buffer Means { float means[]; };
layout(std430, binding = S4D_B_PBWD_LOG_SCALES) readonly buffer LogScales { float log_scales[]; };
layout(std430, binding = S4D_B_PBWD_QUATS) readonly buffer Quats { float quats[]; };
layout(std430, binding = S4D_B_PBWD_OPACITY_LOGITS) readonly buffer OpacityLogits { float opacity_logits[]; };
layout(std430, binding = S4D_B_PBWD_SH) readonly buffer Sh { float sh[]; };
layout(std430, binding = S4D_B_PBWD_COLORS) readonly buffer Colors { float colors[]; };
layout(std430, binding = S4D_B_PBWD_INFO) readonly buffer Info { uvec4 info[]; };
layout(std430, binding = S4D_B_PBWD_CONIC_OPACITY) readonly buffer ConicOpacity { vec4 conic_opacity[]; };
layout(std430, binding = S4D_B_PBWD_GRAD2D) readonly buffer Grad2d { float grad2d[]; };
layout(std430, binding = S4D_B_PBWD_V_MEANS) writeonly buffer VMeans { float v_means[]; };
layout(std430, binding = S4D_B_PBWD_V_LOG_SCALES) writeonly buffer VLogScales { float v_log_scales[]; };
layout(std430, binding = S4D_B_PBWD_V_QUATS) writeonly buffer VQuats { float v_quats[]; };
layout(std430, binding = S4D_B_PBWD_V_OPACITY_LOGITS) writeonly buffer VOpacityLogits { float v_opacity_logits[]; };
layout(std430, binding = S4D_B_PBWD_V_SH) writeonly buffer VSh { float v_sh[]; };
layout(std430, binding = S4D_B_PBWD_V_COLORS) writeonly buffer VColors { float v_colors[]; };

bool use_colors() { return (p.flags & S4D_SPLAT_USE_COLORS) != 0u; }

void write_zeros(uint i) {
  for (uint k = 0u; k < 3u; ++k) v_means[3u * i + k] = 0.0, v_log_scales[3u * i + k] = 0.0;
  for (uint k = 0u; k < 4u; ++k) v_quats[4u * i + k] = 0.0;
  v_opacity_logits[i] = 0.0;
  if (use_colors()) {
    for (uint k = 0u; k < 3u; ++k) v_colors[3u * i + k] = 0.0;
  } else {
    for (uint k = 0u; k < 3u * p.sh_coeffs; ++k) v_sh[3u * p.sh_coeffs * i + k] = 0.0;
  }
}

// Colour backward: SH coefficients (or the colour buffer), and the mean through the view direction.
vec3 color_bwd(uint i, SplatProjection pr, vec3 v_rgb, uint clamped) {
  if (use_colors()) {
    for (uint ch = 0u; ch < 3u; ++ch) v_colors[3u * i + ch] = v_rgb[ch];
    return vec3(0.0);
  }
  vec3 vc = v_rgb;
  for (uint ch = 0u; ch < 3u; ++ch)
    if ((clamped & (1u << ch)) != 0u) vc[ch] = 0.0;
  float Y[S4D_MAX_SH_COEFFS];
  vec3 dY[S4D_MAX_SH_COEFFS];
  sh_basis(p.sh_degree, pr.dir, Y);
  sh_basis_grad(p.sh_degree, pr.dir, dY);
  uint K = p.sh_coeffs, num_active = (p.sh_degree + 1u) * (p.sh_degree + 1u);
  vec3 v_dir = vec3(0.0);
  for (uint k = 0u; k < K; ++k) {
    float f_dot = 0.0;
    for (uint ch = 0u; ch < 3u; ++ch) {
      uint at = (i * K + k) * 3u + ch;
      v_sh[at] = k < num_active ? Y[k] * vc[ch] : 0.0;
      if (k < num_active) f_dot += sh[at] * vc[ch];
    }
    if (k < num_active) v_dir += dY[k] * f_dot;
  }
  // d = (mu - campos)/|mu - campos|: keep the tangent part and divide by the distance.
  return (v_dir - pr.dir * dot(v_dir, pr.dir)) / pr.dist;
}

// Sigma = R S^2 R^T: from the symmetric covariance cotangent G to log-scales and the raw quaternion.
void covariance_bwd(uint i, SplatProjection pr, float G[9]) {
  float vR[9];
  vec3 vs = vec3(0.0);
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 3; ++k) {
      float vN = 0.0;  // cotangent of N = R S, N[r][k] = R[r][k] s_k
      for (int l = 0; l < 3; ++l) vN += 2.0 * G[3 * r + l] * pr.R[3 * l + k] * pr.s[k];
      vR[3 * r + k] = vN * pr.s[k];
      vs[k] += vN * pr.R[3 * r + k];
    }
  for (uint k = 0u; k < 3u; ++k) v_log_scales[3u * i + k] = vs[k] * pr.s[k];

  float w = pr.q.x, x = pr.q.y, y = pr.q.z, z = pr.q.w;
  vec4 vq = 2.0 * vec4(-z * vR[1] + y * vR[2] + z * vR[3] - x * vR[5] - y * vR[6] + x * vR[7],
                       y * vR[1] + z * vR[2] + y * vR[3] - 2.0 * x * vR[4] - w * vR[5] + z * vR[6] + w * vR[7] -
                           2.0 * x * vR[8],
                       -2.0 * y * vR[0] + x * vR[1] + w * vR[2] + x * vR[3] + z * vR[5] - w * vR[6] + z * vR[7] -
                           2.0 * y * vR[8],
                       -2.0 * z * vR[0] - w * vR[1] + x * vR[2] + w * vR[3] - 2.0 * z * vR[4] + y * vR[5] + x * vR[6] +
                           y * vR[7]);
  // Identity fallback: the rotation does not depend on the raw quaternion. Otherwise keep the
  // tangent part of the unit-quaternion gradient and divide by |raw q|.
  vec4 v_raw = pr.q_norm > 0.0 ? (vq - pr.q * dot(vq, pr.q)) / pr.q_norm : vec4(0.0);
  for (uint k = 0u; k < 4u; ++k) v_quats[4u * i + k] = v_raw[k];
}

void main() {
  uint i = flat_group_id() * S4D_SPLAT_WG + gl_LocalInvocationIndex;
  if (i >= p.n) return;
  uvec4 inf = info[i];
  if (inf.z == 0u) {  // radius 0: culled
    write_zeros(i);
    return;
  }
  vec3 mu = vec3(means[3 * i], means[3 * i + 1], means[3 * i + 2]);
  vec3 ls = vec3(log_scales[3 * i], log_scales[3 * i + 1], log_scales[3 * i + 2]);
  vec4 rq = vec4(quats[4 * i], quats[4 * i + 1], quats[4 * i + 2], quats[4 * i + 3]);
  SplatProjection pr = splat_project_one(p.cam, mu, ls, rq);
  vec4 co = conic_opacity[i];
  uint gb = i * S4D_G2D_STRIDE;
  float o = co.w;
  v_opacity_logits[i] = grad2d[gb + S4D_G2D_OPACITY] * o * (1.0 - o);

  vec3 v_rgb = vec3(grad2d[gb + S4D_G2D_RGB], grad2d[gb + S4D_G2D_RGB + 1], grad2d[gb + S4D_G2D_RGB + 2]);
  vec3 v_mu = color_bwd(i, pr, v_rgb, inf.w);

  // Conic = inverse of S2 = [[a, b], [b, c]]: v_S2 = -S2^-1 Gc S2^-1 with Gc symmetric (its
  // off-diagonal holds half of v_B because B appears twice in the matrix).
  float A = co.x, B = co.y, C = co.z;
  float gA = grad2d[gb + S4D_G2D_CONIC], gB = 0.5 * grad2d[gb + S4D_G2D_CONIC + 1], gC = grad2d[gb + S4D_G2D_CONIC + 2];
  float yg00 = A * gA + B * gB, yg01 = A * gB + B * gC, yg10 = B * gA + C * gB, yg11 = B * gB + C * gC;
  float G2[4] = float[4](-(yg00 * A + yg01 * B), -(yg00 * B + yg01 * C), -(yg00 * B + yg01 * C), -(yg10 * B + yg11 * C));

  // S2 = M Sigma M^T: v_Sigma = M^T G2 M, v_M = 2 G2 M Sigma.
  float v_sigma[9];
  for (int k = 0; k < 3; ++k)
    for (int l = 0; l < 3; ++l) {
      float acc = 0.0;
      for (int r0 = 0; r0 < 2; ++r0)
        for (int r1 = 0; r1 < 2; ++r1) acc += pr.M[3 * r0 + k] * G2[2 * r0 + r1] * pr.M[3 * r1 + l];
      v_sigma[3 * k + l] = acc;
    }
  float v_M[6];
  for (int r = 0; r < 2; ++r)
    for (int c = 0; c < 3; ++c) {
      float acc = 0.0;
      for (int r1 = 0; r1 < 2; ++r1)
        for (int k = 0; k < 3; ++k) acc += 2.0 * G2[2 * r + r1] * pr.M[3 * r1 + k] * pr.sigma[3 * k + c];
      v_M[3 * r + c] = acc;
    }
  covariance_bwd(i, pr, v_sigma);

  // M = J W: v_J = v_M W^T; then J(t) with the guard-band clamp (a clamped ratio is constant).
  float v_J[6];
  for (int r = 0; r < 2; ++r)
    for (int c = 0; c < 3; ++c) {
      float acc = 0.0;
      for (int k = 0; k < 3; ++k) acc += v_M[3 * r + k] * pr.W[3 * c + k];
      v_J[3 * r + c] = acc;
    }
  float fx = p.cam.intrinsics.x, fy = p.cam.intrinsics.y;
  float tx = pr.t.x, ty = pr.t.y, tz = pr.t.z;
  vec3 v_t = vec3(0.0);
  float v_rx = -fx / tz * v_J[2], v_ry = -fy / tz * v_J[5];
  v_t.z += -fx / (tz * tz) * v_J[0] - fy / (tz * tz) * v_J[4];
  v_t.z += fx * pr.rx / (tz * tz) * v_J[2] + fy * pr.ry / (tz * tz) * v_J[5];
  if (!pr.clamp_x) v_t.x += v_rx / tz, v_t.z += -v_rx * tx / (tz * tz);
  if (!pr.clamp_y) v_t.y += v_ry / tz, v_t.z += -v_ry * ty / (tz * tz);
  // Screen-space mean (u = fx tx/tz + cx) and depth (= tz).
  float vu = grad2d[gb + S4D_G2D_XY], vv = grad2d[gb + S4D_G2D_XY + 1];
  v_t.x += fx / tz * vu, v_t.y += fy / tz * vv;
  v_t.z += -(fx * tx * vu + fy * ty * vv) / (tz * tz) + grad2d[gb + S4D_G2D_DEPTH];

  for (uint k = 0u; k < 3u; ++k)
    v_means[3u * i + k] = v_mu[k] + pr.W[k] * v_t.x + pr.W[3u + k] * v_t.y + pr.W[6u + k] * v_t.z;
}
