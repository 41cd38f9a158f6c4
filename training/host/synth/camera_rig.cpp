#include "s4d/synth/camera_rig.h"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace s4d::synth {

Ray PinholeCamera::ray(double px, double py) const {
  const double x = (px - 0.5 * width) / focal, y = -(py - 0.5 * height) / focal;
  return {position, normalize(right * x + up * y - back)};
}

std::array<double, 2> PinholeCamera::project(Vec3 world) const {
  const Vec3 d = world - position;
  const double depth = -dot(d, back);
  return {0.5 * width + focal * dot(d, right) / depth, 0.5 * height - focal * dot(d, up) / depth};
}

std::vector<PinholeCamera> arc_cameras(const ArcRig& rig, Vec3 look_at, int count, int width, int height) {
  if (count < 2) throw std::invalid_argument("the camera arc needs at least 2 cameras, got " + std::to_string(count));
  if (width <= 0 || height <= 0)
    throw std::invalid_argument("image size must be positive, got " + std::to_string(width) + "x" +
                                std::to_string(height));
  const double span = rig.span_deg * std::numbers::pi / 180;
  const double focal = 0.5 * width / std::tan(0.5 * rig.fov_x_deg * std::numbers::pi / 180);
  std::vector<PinholeCamera> cams;
  for (int i = 0; i < count; ++i) {
    const double a = -0.5 * span + span * i / (count - 1);
    PinholeCamera c;
    c.position = look_at + Vec3{rig.radius * std::sin(a), rig.height, rig.radius * std::cos(a)};
    c.back = normalize(c.position - look_at);
    c.right = normalize(cross(Vec3{0, 1, 0}, c.back));
    c.up = cross(c.back, c.right);
    c.width = width;
    c.height = height;
    c.focal = focal;
    cams.push_back(c);
  }
  return cams;
}

std::array<double, 15> llff_pose(const PinholeCamera& c) {
  const Vec3 down = -c.up;
  return {down[0], c.right[0], c.back[0], c.position[0], static_cast<double>(c.height),
          down[1], c.right[1], c.back[1], c.position[1], static_cast<double>(c.width),
          down[2], c.right[2], c.back[2], c.position[2], c.focal};
}

}  // namespace s4d::synth
