// One Gaussian's preprocess (ALGORITHMS.md 1.1-1.3), shared by project_fwd and project_bwd so the
// backward recomputes exactly what the forward used. GLSL port of detail::project_one in
// training/ref/include/s4d/ref/splat_project_ref.h; matrices are row-major float[9] as there.
#ifndef SPLAT_PROJECT_GLSL
#define SPLAT_PROJECT_GLSL

#include "quat_normalise.glsl"

struct SplatProjection {
  bool visible;
  vec4 q;          // normalised (w, x, y, z)
  float q_norm;    // |raw quaternion|; 0: identity fallback, no quaternion gradient
  float R[9];      // rotation of the Gaussian
  vec3 s;          // scales
  float sigma[9];  // 3D covariance
  float W[9];      // rotation part of world_to_cam
  vec3 t;          // camera-space mean
  float rx, ry;    // x/z, y/z after the guard-band clamp
  bool clamp_x, clamp_y;
  float M[6];      // J W, 2x3
  float a, b, c, det;  // dilated 2D covariance [[a, b], [b, c]]
  vec3 dir;        // normalize(mean - campos), for SH
  float dist;      // |mean - campos|
};

void splat_quat_to_rot(vec4 q, out float R[9]) {
  float w = q.x, x = q.y, y = q.z, z = q.w;
  R[0] = 1.0 - 2.0 * (y * y + z * z); R[1] = 2.0 * (x * y - w * z);       R[2] = 2.0 * (x * z + w * y);
  R[3] = 2.0 * (x * y + w * z);       R[4] = 1.0 - 2.0 * (x * x + z * z); R[5] = 2.0 * (y * z - w * x);
  R[6] = 2.0 * (x * z - w * y);       R[7] = 2.0 * (y * z + w * x);       R[8] = 1.0 - 2.0 * (x * x + y * y);
}

SplatProjection splat_project_one(SplatCamera cam, vec3 mu, vec3 log_scale, vec4 raw_quat) {
  SplatProjection p;
  p.visible = false;
  vec4 V[3] = vec4[3](cam.view_row0, cam.view_row1, cam.view_row2);
  for (int r = 0; r < 3; ++r) {
    p.W[3 * r] = V[r].x, p.W[3 * r + 1] = V[r].y, p.W[3 * r + 2] = V[r].z;
    p.t[r] = V[r].x * mu.x + V[r].y * mu.y + V[r].z * mu.z + V[r].w;
  }
  // Not in front of the near plane, or infinitely far (a NaN z fails the comparison too).
  if (!(p.t.z > S4D_NEAR_Z) || isinf(p.t.z)) return p;
  // A NaN quaternion would otherwise fall back to the identity on some drivers (max() with NaN is
  // undefined in GLSL): cull it, as the twin does.
  if (any(isnan(raw_quat))) return p;

  splat_normalise_quat(raw_quat, p.q, p.q_norm);
  splat_quat_to_rot(p.q, p.R);
  p.s = exp(log_scale);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) {
      float acc = 0.0;
      for (int k = 0; k < 3; ++k) acc += p.R[3 * r + k] * p.s[k] * p.s[k] * p.R[3 * c + k];
      p.sigma[3 * r + c] = acc;
    }

  // EWA Jacobian with the guard band on x/z and y/z.
  float fx = cam.intrinsics.x, fy = cam.intrinsics.y, tz = p.t.z;
  float lim_x = S4D_GUARD_BAND * float(cam.size.x) / (2.0 * fx);
  float lim_y = S4D_GUARD_BAND * float(cam.size.y) / (2.0 * fy);
  p.rx = p.t.x / tz, p.ry = p.t.y / tz;
  p.clamp_x = abs(p.rx) > lim_x, p.clamp_y = abs(p.ry) > lim_y;
  p.rx = clamp(p.rx, -lim_x, lim_x), p.ry = clamp(p.ry, -lim_y, lim_y);
  float J[6] = float[6](fx / tz, 0.0, -fx * p.rx / tz, 0.0, fy / tz, -fy * p.ry / tz);
  for (int r = 0; r < 2; ++r)
    for (int c = 0; c < 3; ++c)
      p.M[3 * r + c] = J[3 * r] * p.W[c] + J[3 * r + 1] * p.W[3 + c] + J[3 * r + 2] * p.W[6 + c];

  float q00 = 0.0, q01 = 0.0, q11 = 0.0;
  for (int k = 0; k < 3; ++k)
    for (int l = 0; l < 3; ++l) {
      float sg = p.sigma[3 * k + l];
      q00 += p.M[k] * sg * p.M[l];
      q01 += p.M[k] * sg * p.M[3 + l];
      q11 += p.M[3 + k] * sg * p.M[3 + l];
    }
  p.a = q00 + S4D_DILATION, p.b = q01, p.c = q11 + S4D_DILATION;
  p.det = p.a * p.c - p.b * p.b;
  // A PSD covariance plus dilation has det > 0; "not > 0" also catches rounding and NaN.
  p.visible = p.det > 0.0;

  vec3 trans = vec3(V[0].w, V[1].w, V[2].w);
  vec3 campos = -vec3(p.W[0] * trans.x + p.W[3] * trans.y + p.W[6] * trans.z,
                      p.W[1] * trans.x + p.W[4] * trans.y + p.W[7] * trans.z,
                      p.W[2] * trans.x + p.W[5] * trans.y + p.W[8] * trans.z);
  vec3 d = mu - campos;
  p.dist = sqrt(dot(d, d));
  p.dir = d / p.dist;
  return p;
}

#endif  // SPLAT_PROJECT_GLSL
