#include "peer_scene.h"

#include <cmath>
#include <numbers>
#include <random>
#include <string>

#include "s4d/protocols/camera_rig.h"

namespace s4d::bench {

PeerScene make_peer_scene(uint32_t n, uint32_t width, uint32_t height, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1), u01(0, 1);
  std::normal_distribution<double> normal;
  PeerScene s;
  io::GaussianCloud& g = s.cloud;
  g.sh_degree = 3;
  const double log_lo = std::log(0.01), log_hi = std::log(0.15);
  for (uint32_t i = 0; i < n; ++i) {
    double p[3], r2 = 0;
    do {  // rejection: uniform in the unit ball
      r2 = 0;
      for (double& c : p) c = u(rng), r2 += c * c;
    } while (r2 > 1.0);
    for (double c : p) g.means.push_back(static_cast<float>(c));
    for (int k = 0; k < 3; ++k) g.log_scales.push_back(static_cast<float>(log_lo + (log_hi - log_lo) * u01(rng)));
    double q[4], q2 = 0;
    do {  // a normalised 4-D Gaussian sample is a uniform rotation
      q2 = 0;
      for (double& c : q) c = normal(rng), q2 += c * c;
    } while (q2 < 1e-6);
    for (double c : q) g.quats.push_back(static_cast<float>(c / std::sqrt(q2)));
    const double opacity = 0.1 + 0.8 * u01(rng);
    g.opacity_logits.push_back(static_cast<float>(std::log(opacity / (1 - opacity))));
    for (size_t k = 0; k < g.sh_coeffs(); ++k)
      for (int ch = 0; ch < 3; ++ch) g.sh.push_back(static_cast<float>(k == 0 ? u(rng) : 0.2 * u(rng)));
  }
  const double fx = 0.5 * width / std::tan(0.5 * kPeerFovX);
  for (int k = 0; k < kPeerRingCameras; ++k) {
    const double azimuth = 2 * std::numbers::pi * k / kPeerRingCameras;
    io::CameraView v;
    v.name = v.file_path = (k < 10 ? "ring_0" : "ring_") + std::to_string(k);
    v.world_to_cam = protocols::look_at({kPeerRingRadius * std::sin(azimuth), 0, kPeerRingRadius * std::cos(azimuth)},
                                        {0, 0, 0}, {0, 1, 0});
    v.fx = v.fy = fx;
    v.cx = 0.5 * width, v.cy = 0.5 * height;
    v.width = static_cast<int>(width), v.height = static_cast<int>(height);
    s.cameras.push_back(v);
  }
  return s;
}

void write_peer_scene(const std::filesystem::path& dir, const PeerScene& scene) {
  std::filesystem::create_directories(dir);
  io::write_ply_gaussians(dir / "points.ply", scene.cloud);
  io::write_nerf_cameras(dir / "transforms.json", scene.cameras);
}

}  // namespace s4d::bench
