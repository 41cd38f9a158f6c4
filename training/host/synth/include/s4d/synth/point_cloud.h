// The sparse coloured point cloud shipped with the dataset for Gaussian initialisation (the role
// COLMAP's points3D plays for real captures): surface points seen by the cameras at t = 0.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "s4d/synth/camera_rig.h"
#include "s4d/synth/scene.h"

namespace s4d::synth {

struct ColouredPoint {
  float x = 0, y = 0, z = 0;
  uint8_t r = 0, g = 0, b = 0;
};

// About `count` points: the same number of rays per camera through random pixels (seeded), each
// keeping its first hit at t = 0 with the shaded colour the images show there. Sampling through
// the cameras keeps only surfaces the dataset actually observes.
std::vector<ColouredPoint> sample_points(const Scene& scene, const std::vector<PinholeCamera>& cameras, int count,
                                         uint64_t seed);

// `count` points uniform in [-1.3, 1.3]^3 with uniform random colours (seeded): 4DGaussians'
// initialisation of its synthetic D-NeRF scenes, which knows nothing of the surfaces.
std::vector<ColouredPoint> random_points(int count, uint64_t seed);

// ASCII PLY: element vertex with float x, y, z and uchar red, green, blue.
std::string points_to_ply(const std::vector<ColouredPoint>& points);

}  // namespace s4d::synth
