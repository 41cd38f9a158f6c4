#include "s4d/synth/intersect.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace s4d::synth {

std::optional<double> intersect_sphere(const Ray& ray, Vec3 centre, double radius, double s_min, double s_max) {
  // |o + s d - c|^2 = r^2 with |d| = 1: s^2 + 2 b s + c = 0.
  const Vec3 oc = ray.origin - centre;
  const double b = dot(oc, ray.dir);
  const double c = dot(oc, oc) - radius * radius;
  const double disc = b * b - c;
  if (disc < 0) return std::nullopt;
  const double root = std::sqrt(disc);
  for (const double s : {-b - root, -b + root})
    if (s > s_min && s < s_max) return s;
  return std::nullopt;
}

std::optional<double> intersect_plane(const Ray& ray, Vec3 point, Vec3 normal, double s_min, double s_max) {
  const double denom = dot(ray.dir, normal);
  if (std::abs(denom) < 1e-12) return std::nullopt;
  const double s = dot(point - ray.origin, normal) / denom;
  if (s > s_min && s < s_max) return s;
  return std::nullopt;
}

std::optional<std::pair<double, double>> clip_to_box(const Ray& ray, Vec3 lo, Vec3 hi, double s_min, double s_max) {
  double enter = s_min, leave = s_max;
  for (int axis = 0; axis < 3; ++axis) {
    const double o = ray.origin[axis], d = ray.dir[axis];
    const double l = lo[axis], h = hi[axis];
    if (std::abs(d) < 1e-15) {
      if (o < l || o > h) return std::nullopt;
      continue;
    }
    double a = (l - o) / d, b = (h - o) / d;
    if (a > b) std::swap(a, b);
    enter = std::max(enter, a);
    leave = std::min(leave, b);
    if (enter > leave) return std::nullopt;
  }
  return std::pair{enter, leave};
}

std::optional<BoxHit> intersect_box(const Ray& ray, Vec3 half, double s_min, double s_max) {
  // Slab method, remembering which slab set the entry (and the exit, for rays starting inside).
  double enter = -std::numeric_limits<double>::infinity(), leave = std::numeric_limits<double>::infinity();
  BoxHit in, out;
  for (int axis = 0; axis < 3; ++axis) {
    const double o = ray.origin[axis], d = ray.dir[axis], h = half[axis];
    if (std::abs(d) < 1e-15) {
      if (o < -h || o > h) return std::nullopt;
      continue;
    }
    // The face the ray meets first on this axis is the one facing against its direction.
    const int near_sign = d > 0 ? -1 : 1;
    const double a = (near_sign * h - o) / d, b = (-near_sign * h - o) / d;
    if (a > enter) {
      enter = a;
      in = {a, axis, near_sign};
    }
    if (b < leave) {
      leave = b;
      out = {b, axis, -near_sign};
    }
  }
  if (enter > leave) return std::nullopt;
  if (enter > s_min && enter < s_max) return in;
  if (leave > s_min && leave < s_max) return out;
  return std::nullopt;
}

}  // namespace s4d::synth
