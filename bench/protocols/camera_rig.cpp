// The spiral trajectory from the training rig; conventions and parameters in camera_rig.h.
#include "s4d/protocols/camera_rig.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <set>
#include <stdexcept>
#include <string>


namespace s4d::protocols {
namespace {

constexpr double kForwardFacingCos = 0.5;  // 60 degrees: see camera_rig.h
constexpr double kMaxElevation = std::numbers::pi / 3;
constexpr double kSingularRatio = 1e-6;

Vec3 row(const io::CameraView& v, int r) { return {v.world_to_cam[4 * r], v.world_to_cam[4 * r + 1], v.world_to_cam[4 * r + 2]}; }

double det3(const std::array<double, 9>& m) {
  return m[0] * (m[4] * m[8] - m[5] * m[7]) - m[1] * (m[3] * m[8] - m[5] * m[6]) + m[2] * (m[3] * m[7] - m[4] * m[6]);
}

// Cramer's rule; the caller has checked the determinant.
Vec3 solve3(const std::array<double, 9>& m, const Vec3& b) {
  const double d = det3(m);
  Vec3 x{};
  for (int c = 0; c < 3; ++c) {
    std::array<double, 9> mc = m;
    for (int r = 0; r < 3; ++r) mc[3 * r + c] = b[r];
    x[c] = det3(mc) / d;
  }
  return x;
}

// Least-squares point nearest to every axis, or nullopt-like false when the axes are near parallel.
bool nearest_to_axes(const std::vector<io::CameraView>& cams, Vec3& out) {
  std::array<double, 9> a{};
  Vec3 b{};
  for (const io::CameraView& v : cams) {
    const Vec3 d = camera_axis(v), c = camera_centre(v);
    for (int r = 0; r < 3; ++r)
      for (int k = 0; k < 3; ++k) {
        const double p = (r == k ? 1.0 : 0.0) - d[r] * d[k];
        a[3 * r + k] += p;
        b[r] += p * c[k];
      }
  }
  const double scale = (a[0] + a[4] + a[8]) / 3;
  if (!(det3(a) > kSingularRatio * scale * scale * scale)) return false;
  out = solve3(a, b);
  return true;
}

double percentile90(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const double pos = 0.9 * double(v.size() - 1);
  const size_t lo = static_cast<size_t>(pos);
  const size_t hi = std::min(lo + 1, v.size() - 1);
  return v[lo] + (pos - double(lo)) * (v[hi] - v[lo]);
}

ProtocolFrame frame_at(const RigSummary& rig, int k, int frames, const Vec3& position) {
  ProtocolFrame f;
  f.index = k;
  f.time = frames == 1 ? 0.0 : double(k) / double(frames - 1);
  f.camera = rig.cameras.front();
  f.camera.name = "spiral";
  f.camera.time = f.time;
  f.camera.world_to_cam = look_at(position, rig.centre, rig.up);
  return f;
}

}  // namespace

Vec3 camera_centre(const io::CameraView& v) {
  const Vec3 t{v.world_to_cam[3], v.world_to_cam[7], v.world_to_cam[11]};
  Vec3 c{};
  for (int r = 0; r < 3; ++r) c = c - t[r] * row(v, r);
  return c;
}

Vec3 camera_axis(const io::CameraView& v) { return normalize(row(v, 2)); }

std::array<double, 16> look_at(const Vec3& position, const Vec3& target, const Vec3& up) {
  const Vec3 z = normalize(target - position);
  const Vec3 side = cross(z, up);
  if (!(norm(side) > 1e-9)) throw std::invalid_argument("look_at: the view direction is parallel to the up vector");
  const Vec3 x = normalize(side), y = cross(z, x);  // x right, y down, z forward
  std::array<double, 16> m{};
  const Vec3 rows[3] = {x, y, z};
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) m[4 * r + c] = rows[r][c];
    m[4 * r + 3] = -dot(rows[r], position);
  }
  m[15] = 1;
  return m;
}

RigSummary analyse_rig(const data::Dataset& dataset) {
  RigSummary rig;
  std::set<std::string> seen;
  for (const data::View& v : dataset.views)
    if (!v.test && seen.insert(camera_name(v)).second) rig.cameras.push_back(v.camera);
  if (rig.cameras.empty())
    throw std::invalid_argument("spiral: " + dataset.root.string() + " has no training views to design the path from");
  Vec3 up{}, axis_sum{}, centre_sum{};
  for (const io::CameraView& v : rig.cameras) {
    up = up - row(v, 1);
    axis_sum = axis_sum + camera_axis(v);
    centre_sum = centre_sum + camera_centre(v);
  }
  const double n = double(rig.cameras.size());
  rig.up = normalize(up);
  rig.mean_centre = (1.0 / n) * centre_sum;
  // A full ring's axes cancel: no mean axis, so the rig surrounds the scene.
  rig.mean_axis = norm(axis_sum) > 1e-6 * n ? normalize(axis_sum) : rig.up;
  rig.forward_facing = norm(axis_sum) > 1e-6 * n;
  for (const io::CameraView& v : rig.cameras)
    rig.forward_facing = rig.forward_facing && dot(camera_axis(v), rig.mean_axis) > kForwardFacingCos;
  if (!nearest_to_axes(rig.cameras, rig.centre))
    rig.centre = rig.mean_centre + (dataset.extent > 0 ? dataset.extent : 1.0) * rig.mean_axis;
  return rig;
}

std::vector<ProtocolFrame> spiral_frames(const RigSummary& rig, int frames) {
  if (frames < 1) throw std::invalid_argument("spiral: the frame count must be at least 1, got " + std::to_string(frames));
  std::vector<ProtocolFrame> out;
  if (rig.forward_facing) {
    const Vec3 z = rig.mean_axis, x = normalize(cross(z, rig.up)), y = cross(z, x);
    Vec3 radii{};
    const Vec3 axes[3] = {x, y, z};
    for (int a = 0; a < 3; ++a) {
      std::vector<double> offsets;
      for (const io::CameraView& v : rig.cameras) offsets.push_back(std::abs(dot(camera_centre(v) - rig.mean_centre, axes[a])));
      radii[a] = percentile90(offsets);
    }
    if (!(radii[0] > 0 || radii[1] > 0))
      throw std::invalid_argument("spiral: the training cameras all sit at one position, so a forward-facing rig gives "
                                  "no spiral radius; render a fixed camera with --path train:CAM");
    for (int k = 0; k < frames; ++k) {
      const double theta = 4 * std::numbers::pi * k / frames;
      const Vec3 p = rig.mean_centre + radii[0] * std::cos(theta) * x + radii[1] * std::sin(theta) * y +
                     radii[2] * std::sin(0.5 * theta) * z;
      out.push_back(frame_at(rig, k, frames, p));
    }
    return out;
  }
  double radius = 0, h_lo = INFINITY, h_hi = -INFINITY;
  for (const io::CameraView& v : rig.cameras) {
    const Vec3 o = camera_centre(v) - rig.centre;
    const double h = dot(o, rig.up);
    radius += norm(o - h * rig.up) / double(rig.cameras.size());
    h_lo = std::min(h_lo, h), h_hi = std::max(h_hi, h);
  }
  if (!(radius > 1e-9))
    throw std::invalid_argument("spiral: the training cameras all sit on the up axis through the centre, so the orbit "
                                "has no radius; render a fixed camera with --path train:CAM");
  const double h_max = radius * std::tan(kMaxElevation);
  h_lo = std::clamp(h_lo, -h_max, h_max), h_hi = std::clamp(h_hi, -h_max, h_max);
  Vec3 e1 = camera_centre(rig.cameras.front()) - rig.centre;
  e1 = e1 - dot(e1, rig.up) * rig.up;
  if (!(norm(e1) > 1e-9)) e1 = cross(rig.up, std::abs(rig.up[0]) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0});
  e1 = normalize(e1);
  const Vec3 e2 = cross(rig.up, e1);
  for (int k = 0; k < frames; ++k) {
    const double theta = 2 * std::numbers::pi * k / frames;
    const double h = frames == 1 ? h_lo : h_lo + (h_hi - h_lo) * k / (frames - 1);
    out.push_back(frame_at(rig, k, frames, rig.centre + radius * std::cos(theta) * e1 + radius * std::sin(theta) * e2 + h * rig.up));
  }
  return out;
}

}  // namespace s4d::protocols
