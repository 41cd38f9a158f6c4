#include "s4d/data/camera_geometry.h"

#include <cmath>

namespace s4d::data {

Vec3 camera_centre(const io::CameraView& camera) {
  const auto& m = camera.world_to_cam;
  Vec3 o{};
  for (size_t i = 0; i < 3; ++i) o[i] = -(m[i] * m[3] + m[4 + i] * m[7] + m[8 + i] * m[11]);
  return o;
}

Vec3 to_camera(const io::CameraView& camera, const Vec3& p) {
  const auto& m = camera.world_to_cam;
  Vec3 x{};
  for (size_t i = 0; i < 3; ++i) x[i] = m[i * 4] * p[0] + m[i * 4 + 1] * p[1] + m[i * 4 + 2] * p[2] + m[i * 4 + 3];
  return x;
}

bool sees(const io::CameraView& camera, const Vec3& p) {
  const Vec3 x = to_camera(camera, p);
  if (x[2] <= 1e-6) return false;
  const double u = camera.fx * x[0] / x[2] + camera.cx, v = camera.fy * x[1] / x[2] + camera.cy;
  return u >= 0 && u < camera.width && v >= 0 && v < camera.height;
}

std::optional<Vec3> nearest_to_optical_axes(const std::vector<const io::CameraView*>& cameras) {
  double a[3][3] = {};
  Vec3 b{};
  for (const io::CameraView* cam : cameras) {
    const Vec3 c = camera_centre(*cam);
    Vec3 d{cam->world_to_cam[8], cam->world_to_cam[9], cam->world_to_cam[10]};  // forward (third row of R)
    const double n = std::hypot(d[0], d[1], d[2]);
    if (!(n > 0)) continue;
    for (double& x : d) x /= n;
    for (size_t i = 0; i < 3; ++i) {
      for (size_t j = 0; j < 3; ++j) {
        const double m = (i == j ? 1.0 : 0.0) - d[i] * d[j];
        a[i][j] += m;
        b[i] += m * c[j];
      }
    }
  }
  auto det3 = [](const double m[3][3]) {
    return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
           m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
  };
  const double det = det3(a);
  const double scale = (a[0][0] + a[1][1] + a[2][2]) / 3;
  if (!(scale > 0) || !(std::abs(det) > 1e-6 * scale * scale * scale)) return std::nullopt;
  Vec3 p{};
  for (size_t k = 0; k < 3; ++k) {  // Cramer's rule
    double m[3][3];
    for (size_t i = 0; i < 3; ++i) {
      for (size_t j = 0; j < 3; ++j) m[i][j] = j == k ? b[i] : a[i][j];
    }
    p[k] = det3(m) / det;
  }
  return p;
}

}  // namespace s4d::data
