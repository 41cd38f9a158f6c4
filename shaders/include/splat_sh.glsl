// Real spherical harmonics basis of degree 0..3 (graphdeco auxiliary.h constants) and its
// derivative with x, y, z treated as independent (callers project onto the sphere's tangent).
// GLSL port of detail::sh_basis in training/ref/include/s4d/ref/splat_project_ref.h.
#ifndef SPLAT_SH_GLSL
#define SPLAT_SH_GLSL

const float SH_C0 = 0.28209479177387814;
const float SH_C1 = 0.4886025119029199;
const float SH_C2[5] = float[5](1.0925484305920792, -1.0925484305920792, 0.31539156525252005, -1.0925484305920792,
                                0.5462742152960396);
const float SH_C3[7] = float[7](-0.5900435899266435, 2.890611442640554, -0.4570457994644658, 0.3731763325901154,
                                -0.4570457994644658, 1.445305721320277, -0.5900435899266435);

void sh_basis(uint degree, vec3 d, out float Y[S4D_MAX_SH_COEFFS]) {
  float x = d.x, y = d.y, z = d.z;
  float xx = x * x, yy = y * y, zz = z * z;
  for (int k = 0; k < S4D_MAX_SH_COEFFS; ++k) Y[k] = 0.0;
  Y[0] = SH_C0;
  if (degree >= 1u) {
    Y[1] = -SH_C1 * y, Y[2] = SH_C1 * z, Y[3] = -SH_C1 * x;
  }
  if (degree >= 2u) {
    Y[4] = SH_C2[0] * x * y, Y[5] = SH_C2[1] * y * z, Y[6] = SH_C2[2] * (2.0 * zz - xx - yy);
    Y[7] = SH_C2[3] * x * z, Y[8] = SH_C2[4] * (xx - yy);
  }
  if (degree >= 3u) {
    Y[9] = SH_C3[0] * y * (3.0 * xx - yy), Y[10] = SH_C3[1] * x * y * z;
    Y[11] = SH_C3[2] * y * (4.0 * zz - xx - yy), Y[12] = SH_C3[3] * z * (2.0 * zz - 3.0 * xx - 3.0 * yy);
    Y[13] = SH_C3[4] * x * (4.0 * zz - xx - yy), Y[14] = SH_C3[5] * z * (xx - yy);
    Y[15] = SH_C3[6] * x * (xx - 3.0 * yy);
  }
}

void sh_basis_grad(uint degree, vec3 d, out vec3 dY[S4D_MAX_SH_COEFFS]) {
  float x = d.x, y = d.y, z = d.z;
  float xx = x * x, yy = y * y, zz = z * z;
  for (int k = 0; k < S4D_MAX_SH_COEFFS; ++k) dY[k] = vec3(0.0);
  if (degree >= 1u) {
    dY[1] = vec3(0.0, -SH_C1, 0.0), dY[2] = vec3(0.0, 0.0, SH_C1), dY[3] = vec3(-SH_C1, 0.0, 0.0);
  }
  if (degree >= 2u) {
    dY[4] = vec3(SH_C2[0] * y, SH_C2[0] * x, 0.0);
    dY[5] = vec3(0.0, SH_C2[1] * z, SH_C2[1] * y);
    dY[6] = vec3(-2.0 * SH_C2[2] * x, -2.0 * SH_C2[2] * y, 4.0 * SH_C2[2] * z);
    dY[7] = vec3(SH_C2[3] * z, 0.0, SH_C2[3] * x);
    dY[8] = vec3(2.0 * SH_C2[4] * x, -2.0 * SH_C2[4] * y, 0.0);
  }
  if (degree >= 3u) {
    dY[9] = vec3(SH_C3[0] * 6.0 * x * y, SH_C3[0] * (3.0 * xx - 3.0 * yy), 0.0);
    dY[10] = vec3(SH_C3[1] * y * z, SH_C3[1] * x * z, SH_C3[1] * x * y);
    dY[11] = vec3(-2.0 * SH_C3[2] * x * y, SH_C3[2] * (4.0 * zz - xx - 3.0 * yy), 8.0 * SH_C3[2] * y * z);
    dY[12] = vec3(-6.0 * SH_C3[3] * x * z, -6.0 * SH_C3[3] * y * z, SH_C3[3] * (6.0 * zz - 3.0 * xx - 3.0 * yy));
    dY[13] = vec3(SH_C3[4] * (4.0 * zz - 3.0 * xx - yy), -2.0 * SH_C3[4] * x * y, 8.0 * SH_C3[4] * x * z);
    dY[14] = vec3(2.0 * SH_C3[5] * x * z, -2.0 * SH_C3[5] * y * z, SH_C3[5] * (xx - yy));
    dY[15] = vec3(SH_C3[6] * (3.0 * xx - 3.0 * yy), -6.0 * SH_C3[6] * x * y, 0.0);
  }
}

#endif  // SPLAT_SH_GLSL
