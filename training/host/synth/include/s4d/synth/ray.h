// Rays for the synthetic scene's ray caster, on the host's Vec3 (s4d/util/vec3.h), with the two
// operations only the scene needs.
#pragma once
#include <cmath>

#include "s4d/util/vec3.h"

namespace s4d::synth {

// Componentwise product (albedo tints, scaling into a body's unit frame).
inline Vec3 mul(const Vec3& a, const Vec3& b) { return {a[0] * b[0], a[1] * b[1], a[2] * b[2]}; }

// Rotation about the world +y axis by `angle` radians (counter-clockwise seen from above).
inline Vec3 rotate_y(const Vec3& v, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  return {c * v[0] + s * v[2], v[1], -s * v[0] + c * v[2]};
}

// dir is unit length; points on the ray are origin + s * dir.
struct Ray {
  Vec3 origin{}, dir{};
  Vec3 at(double s) const { return origin + dir * s; }
};

}  // namespace s4d::synth
