// Pinhole cameras of the synthetic dataset: a Neu3D-like rig, N cameras on a horizontal arc all
// looking at the scene centre, with one common focal length and image size.
#pragma once
#include <array>
#include <vector>

#include "s4d/synth/ray.h"

namespace s4d::synth {

// Camera-to-world in OpenGL axes: right, up, back (the camera looks along -back). The principal
// point is the image centre; pixel (i, j) covers [i, i+1] x [j, j+1], rows from the top.
struct PinholeCamera {
  Vec3 position{}, right{}, up{}, back{};
  int width = 0, height = 0;
  double focal = 0;  // pixels

  // The ray through image point (px, py) in pixel units (pixel centres at +0.5).
  Ray ray(double px, double py) const;
  // Image point of a world point in front of the camera.
  std::array<double, 2> project(Vec3 world) const;
  // Depth along the viewing axis (what LLFF near/far bounds measure).
  double view_depth(Vec3 world) const { return -dot(world - position, back); }
};

struct ArcRig {
  double radius = 4.0;      // distance from the look-at point in the horizontal plane
  double height = 0.6;      // camera height above the look-at point
  double span_deg = 75.0;   // angle from the first to the last camera
  double fov_x_deg = 50.0;  // horizontal field of view
};

// Cameras ordered left to right (seen from behind the rig), the middle of the arc on +z.
// Throws std::invalid_argument for count < 2 or a non-positive size.
std::vector<PinholeCamera> arc_cameras(const ArcRig& rig, Vec3 look_at, int count, int width, int height);

// The LLFF 3x5 matrix, row-major: columns (down, right, back, centre, (H, W, focal)) where
// down = -up; this is what each poses_bounds.npy row stores before near and far.
std::array<double, 15> llff_pose(const PinholeCamera& camera);

}  // namespace s4d::synth
