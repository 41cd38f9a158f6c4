// The host's 3-vector and the arithmetic its users share: camera rigs and paths, the viewer's camera,
// the dataset checks and the synthetic scene's ray caster, all in double so that geometry used as
// ground truth is not limited by float rounding. Vec3Of<T> is the same in another scalar type (the
// CPU twins run in float and in double). Device buffers never hold it (std430 pads a vec3 to 16 bytes:
// shaders/shared holds flat float arrays).
#pragma once
#include <array>
#include <cmath>

namespace s4d {

template <class T>
using Vec3Of = std::array<T, 3>;
using Vec3 = Vec3Of<double>;

inline Vec3 operator+(const Vec3& a, const Vec3& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
inline Vec3 operator-(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
inline Vec3 operator-(const Vec3& a) { return {-a[0], -a[1], -a[2]}; }
inline Vec3 operator*(const Vec3& a, double s) { return {a[0] * s, a[1] * s, a[2] * s}; }
inline Vec3 operator*(double s, const Vec3& a) { return a * s; }
inline double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline double norm(const Vec3& a) { return std::sqrt(dot(a, a)); }
inline Vec3 normalize(const Vec3& a) { return a * (1.0 / norm(a)); }

}  // namespace s4d
