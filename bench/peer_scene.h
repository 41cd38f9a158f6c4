// The PyTorch peer's (hbb1/torch-splatting) kind of benchmark scene, rebuilt from its description: n Gaussians
// with means uniform in the unit ball, per-axis scales log-uniform in [0.01, 0.15], SH degree 3, seen
// by camera 0 of a ring of cameras looking at the origin. Written as a standard 3DGS PLY and a
// transforms.json, other tools (the peer, `style4d render`) draw exactly the same scene.
#pragma once
#include <cstdint>
#include <filesystem>
#include <vector>

#include "s4d/io/nerf_cameras.h"
#include "s4d/io/ply_gaussians.h"

namespace s4d::bench {

// The ring: kPeerRingCameras cameras evenly spaced on a horizontal circle of radius kPeerRingRadius
// about the origin (camera k at azimuth 2 pi k / count, camera 0 on +z), each looking at the origin
// with world +y up, kPeerFovX horizontal field of view, square pixels, principal point at the centre.
inline constexpr int kPeerRingCameras = 8;
inline constexpr double kPeerRingRadius = 3.0;
inline constexpr double kPeerFovX = 1.0471975511965976;  // 60 degrees

struct PeerScene {
  io::GaussianCloud cloud;
  std::vector<io::CameraView> cameras;  // the ring, named ring_00, ring_01, ...
};

// Opacities are uniform in [0.1, 0.9] (stored as logits), rotations uniform, SH DC coefficients
// uniform in [-1, 1] and the higher ones in [-0.2, 0.2]. The same (n, width, height, seed) gives the
// same scene.
PeerScene make_peer_scene(uint32_t n, uint32_t width, uint32_t height, uint32_t seed = 1);

// Writes dir/points.ply and dir/transforms.json (creating dir).
void write_peer_scene(const std::filesystem::path& dir, const PeerScene& scene);

}  // namespace s4d::bench
