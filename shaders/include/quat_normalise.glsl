// Robust quaternion normalisation, shared by the projection (splat_project.glsl) and densify_split,
// so a split child is rotated as its parent renders. Twin: normalise_quat in
// training/ref/include/s4d/ref/splat_project_ref.h.
#ifndef QUAT_NORMALISE_GLSL
#define QUAT_NORMALISE_GLSL

// Divides by the largest component first so tiny quaternions (1e-20 components) do not underflow;
// zero or non-finite input gives the identity rotation and q_norm = 0.
void splat_normalise_quat(vec4 raw, out vec4 q, out float norm) {
  vec4 m = abs(raw);
  float big = max(max(m.x, m.y), max(m.z, m.w));
  if (!(big > 0.0) || isinf(big) || isnan(big)) {
    q = vec4(1.0, 0.0, 0.0, 0.0);
    norm = 0.0;
    return;
  }
  vec4 r = raw / big;
  float root = sqrt(dot(r, r));
  q = r / root;
  norm = big * root;
}

#endif
