// Analytic ray-primitive intersections. Each returns the nearest hit with ray parameter s in the
// open interval (s_min, s_max), or nothing.
#pragma once
#include <optional>
#include <utility>

#include "s4d/synth/ray.h"

namespace s4d::synth {

std::optional<double> intersect_sphere(const Ray& ray, Vec3 centre, double radius, double s_min, double s_max);

// The infinite plane through `point` with normal `normal` (either side); nothing for a ray
// parallel to it.
std::optional<double> intersect_plane(const Ray& ray, Vec3 point, Vec3 normal, double s_min, double s_max);

struct BoxHit {
  double s = 0;
  int axis = 0;  // 0, 1, 2: the face hit is perpendicular to x, y or z
  int sign = 1;  // +1 or -1: which of the two faces on that axis
};

// The axis-aligned box [-half, half] centred at the origin (slab method). Moving or turned boxes
// transform the ray into the box frame first.
std::optional<BoxHit> intersect_box(const Ray& ray, Vec3 half, double s_min, double s_max);

// The parameter interval where the ray is inside the axis-aligned box [lo, hi], clipped to
// [s_min, s_max]; nothing when it is empty.
std::optional<std::pair<double, double>> clip_to_box(const Ray& ray, Vec3 lo, Vec3 hi, double s_min, double s_max);

}  // namespace s4d::synth
