#include "s4d/synth/point_cloud.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "s4d/synth/hash_rng.h"

namespace s4d::synth {
namespace {

uint8_t to_byte(double v) { return static_cast<uint8_t>(std::lround(std::clamp(v, 0.0, 1.0) * 255)); }

// Distinguishes this stream from the pixel jitter that uses the same seed.
constexpr uint64_t kPointStream = 0x90196c10d5ull;
constexpr uint64_t kRandomInitStream = 0x5eed0c10d0ull;

}  // namespace

std::vector<ColouredPoint> random_points(int count, uint64_t seed) {
  std::vector<ColouredPoint> points(static_cast<size_t>(std::max(count, 0)));
  for (size_t i = 0; i < points.size(); ++i) {
    double u[6];
    for (uint64_t a = 0; a < 6; ++a) u[a] = unit_double(hash_key(seed ^ kRandomInitStream, i, a));
    points[i] = {static_cast<float>(u[0] * 2.6 - 1.3), static_cast<float>(u[1] * 2.6 - 1.3),
                 static_cast<float>(u[2] * 2.6 - 1.3), to_byte(u[3]), to_byte(u[4]), to_byte(u[5])};
  }
  return points;
}

std::vector<ColouredPoint> sample_points(const Scene& scene, const std::vector<PinholeCamera>& cameras, int count,
                                         uint64_t seed) {
  std::vector<ColouredPoint> points;
  if (cameras.empty() || count <= 0) return points;
  const int per_camera = (count + static_cast<int>(cameras.size()) - 1) / static_cast<int>(cameras.size());
  for (size_t c = 0; c < cameras.size(); ++c) {
    const PinholeCamera& cam = cameras[c];
    for (int k = 0; k < per_camera; ++k) {
      const uint64_t h = hash_key(seed ^ kPointStream, c, static_cast<uint64_t>(k));
      const Ray ray = cam.ray(unit_double(h) * cam.width, unit_double(mix64(h)) * cam.height);
      const auto hit = trace(scene, ray, 0.0);
      if (!hit) continue;
      const Vec3 colour = shade(scene, *hit, ray.dir);
      points.push_back({static_cast<float>(hit->point[0]), static_cast<float>(hit->point[1]),
                        static_cast<float>(hit->point[2]), to_byte(colour[0]), to_byte(colour[1]), to_byte(colour[2])});
    }
  }
  return points;
}

std::string points_to_ply(const std::vector<ColouredPoint>& points) {
  std::ostringstream out;
  out << "ply\nformat ascii 1.0\ncomment style4d synth: surface points at t = 0\nelement vertex " << points.size()
      << "\nproperty float x\nproperty float y\nproperty float z\n"
         "property uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n";
  out.precision(7);
  for (const ColouredPoint& p : points)
    out << p.x << ' ' << p.y << ' ' << p.z << ' ' << int{p.r} << ' ' << int{p.g} << ' ' << int{p.b} << '\n';
  return out.str();
}

}  // namespace s4d::synth
