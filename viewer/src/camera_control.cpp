#include "s4d/viewer/camera_control.h"

#include <algorithm>
#include <cmath>

namespace s4d::viewer {

namespace {

// Pitch stops where the forward axis is this close (cosine) to the up axis: past it the orbit
// would flip over the pole.
constexpr double kMaxForwardUpCosine = 0.98;

// Rodrigues: v rotated by `angle` about the unit `axis`.
Vec3 rotate(const Vec3& v, const Vec3& axis, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  return v * c + cross(axis, v) * s + axis * (dot(axis, v) * (1 - c));
}

}  // namespace

CameraControl::CameraControl(const Vec3& up, double speed) : up_(normalize(up)), speed_(speed) {
  axes_ = {Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, 0, 1}};
  pivot_ = {0, 0, 1};
}

void CameraControl::snap(const io::CameraView& camera, double pivot_depth) {
  const auto& m = camera.world_to_cam;
  for (int k = 0; k < 3; ++k) axes_[k] = {m[4 * k], m[4 * k + 1], m[4 * k + 2]};
  for (int j = 0; j < 3; ++j) position_[j] = -(m[j] * m[3] + m[4 + j] * m[7] + m[8 + j] * m[11]);
  pivot_ = position_ + axes_[2] * pivot_depth;
  focal_per_height_ = camera.fy / camera.height;
  aspect_ = camera.fx / camera.fy;
}

void CameraControl::rotate_about_pivot(const Vec3& axis, double angle) {
  if (angle == 0) return;  // no input leaves the pose bit for bit (the viewer reuses still frames)
  position_ = pivot_ + rotate(position_ - pivot_, axis, angle);
  for (Vec3& a : axes_) a = rotate(a, axis, angle);
  // Re-orthonormalise so many small turns do not accumulate drift.
  axes_[2] = normalize(axes_[2]);
  axes_[0] = normalize(cross(axes_[1], axes_[2]));
  axes_[1] = cross(axes_[2], axes_[0]);
}

void CameraControl::orbit(double yaw, double pitch) {
  rotate_about_pivot(up_, yaw);
  const Vec3 forward = rotate(axes_[2], axes_[0], pitch);
  if (std::abs(dot(forward, up_)) < kMaxForwardUpCosine) rotate_about_pivot(axes_[0], pitch);
}

void CameraControl::pan(double dx, double dy, double height) {
  const double per_pixel = norm(pivot_ - position_) / (focal_per_height_ * height);
  const Vec3 delta = (axes_[0] * dx + axes_[1] * dy) * -per_pixel;
  position_ = position_ + delta;
  pivot_ = pivot_ + delta;
}

void CameraControl::zoom(double steps) {
  if (steps == 0) return;
  const double distance = std::max(1e-3, norm(pivot_ - position_) * std::pow(0.9, steps));
  position_ = pivot_ - axes_[2] * distance;
}

void CameraControl::fly(double forward, double right, double up, double seconds) {
  const Vec3 dir = axes_[2] * forward + axes_[0] * right + axes_[1] * -up;
  const Vec3 delta = dir * (speed_ * seconds);
  position_ = position_ + delta;
  pivot_ = pivot_ + delta;
}

io::CameraView CameraControl::view(uint32_t width, uint32_t height, const std::string& name, double time) const {
  io::CameraView v;
  v.name = name;
  v.file_path = "./" + name;
  for (int k = 0; k < 3; ++k) {
    for (int j = 0; j < 3; ++j) v.world_to_cam[4 * k + j] = axes_[k][j];
    v.world_to_cam[4 * k + 3] = -dot(axes_[k], position_);
  }
  v.world_to_cam[15] = 1;
  v.fy = focal_per_height_ * height;
  v.fx = v.fy * aspect_;
  v.cx = width / 2.0, v.cy = height / 2.0;
  v.width = static_cast<int>(width), v.height = static_cast<int>(height);
  v.time = time;
  return v;
}

splat::Camera CameraControl::camera(uint32_t width, uint32_t height) const {
  const io::CameraView v = view(width, height, "viewer", 0);
  splat::Camera cam;
  for (size_t k = 0; k < 12; ++k) cam.world_to_cam[k] = static_cast<float>(v.world_to_cam[k]);
  cam.fx = static_cast<float>(v.fx), cam.fy = static_cast<float>(v.fy);
  cam.cx = static_cast<float>(v.cx), cam.cy = static_cast<float>(v.cy);
  cam.width = width, cam.height = height;
  return cam;
}

Vec3 estimate_up(const std::vector<io::CameraView>& cameras) {
  Vec3 sum{0, 0, 0};
  for (const io::CameraView& c : cameras) sum = sum - Vec3{c.world_to_cam[4], c.world_to_cam[5], c.world_to_cam[6]};
  if (norm(sum) < 1e-6) return {0, 0, 1};
  return normalize(sum);
}

double median_depth(const io::CameraView& camera, const std::vector<float>& means, double fallback) {
  const auto& m = camera.world_to_cam;
  std::vector<double> depths;
  for (size_t i = 0; i + 2 < means.size(); i += 3) {
    const double z = m[8] * means[i] + m[9] * means[i + 1] + m[10] * means[i + 2] + m[11];
    if (z > 0) depths.push_back(z);
  }
  if (depths.empty()) return fallback;
  std::nth_element(depths.begin(), depths.begin() + static_cast<long>(depths.size() / 2), depths.end());
  return depths[depths.size() / 2];
}

}  // namespace s4d::viewer
