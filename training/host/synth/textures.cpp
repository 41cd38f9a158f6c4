#include "s4d/synth/textures.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "s4d/synth/hash_rng.h"

namespace s4d::synth {
namespace {

// One mix per lattice point: the noise is evaluated for every sample on the wall and the floor.
double lattice(long long i, long long j) {
  return unit_double(mix64(static_cast<uint64_t>(i) * 0x9e3779b97f4a7c15ull ^ static_cast<uint64_t>(j) * 0xc2b2ae3d27d4eb4full));
}

double smooth(double u) { return u * u * (3 - 2 * u); }

Vec3 lerp(Vec3 a, Vec3 b, double u) { return a + (b - a) * u; }

bool checker(double a, double b) {
  return (static_cast<long long>(std::floor(a)) + static_cast<long long>(std::floor(b))) % 2 != 0;
}

// Hue wheel at full saturation, h in [0, 1).
Vec3 hue(double h) {
  const double r = std::clamp(std::abs(h * 6 - 3) - 1, 0.0, 1.0);
  const double g = std::clamp(2 - std::abs(h * 6 - 2), 0.0, 1.0);
  const double b = std::clamp(2 - std::abs(h * 6 - 4), 0.0, 1.0);
  return {r, g, b};
}

}  // namespace

double value_noise(double x, double y) {
  const double fx = std::floor(x), fy = std::floor(y);
  const auto i = static_cast<long long>(fx), j = static_cast<long long>(fy);
  const double u = smooth(x - fx), v = smooth(y - fy);
  const double a = lattice(i, j), b = lattice(i + 1, j), c = lattice(i, j + 1), d = lattice(i + 1, j + 1);
  return (a * (1 - u) + b * u) * (1 - v) + (c * (1 - u) + d * u) * v;
}

Vec3 wall_albedo(double x, double y) {
  // Brick-like checker in two warm colours, broken up by two octaves of noise.
  const Vec3 base = checker(x / 0.5, y / 0.35) ? Vec3{0.75, 0.45, 0.30} : Vec3{0.90, 0.80, 0.55};
  const double n = 0.6 * value_noise(x * 3, y * 3) + 0.4 * value_noise(x * 11 + 7, y * 11 + 3);
  return lerp(base, Vec3{0.35, 0.30, 0.45}, 0.45 * n);
}

Vec3 floor_albedo(double x, double z) {
  // Blue/grey stripes along x crossed by a larger green checker, plus noise.
  const bool stripe = std::fmod(std::abs(x) / 0.2, 2.0) < 1.0;
  Vec3 base = stripe ? Vec3{0.30, 0.45, 0.75} : Vec3{0.70, 0.72, 0.78};
  if (checker(x / 0.8, z / 0.8)) base = mul(base, Vec3{0.6, 1.0, 0.6});
  const double n = value_noise(x * 6 + 13, z * 6 + 29);
  return base * (0.75 + 0.35 * n);
}

Vec3 sphere_albedo(Vec3 local_dir) {
  // Colour follows longitude (so any turn about the axis changes it), a latitude checker on top.
  const double lon = std::atan2(local_dir[0], local_dir[2]) / (2 * std::numbers::pi) + 0.5;
  const double lat = std::asin(std::clamp(local_dir[1], -1.0, 1.0)) / std::numbers::pi + 0.5;
  const Vec3 c = hue(std::fmod(lon, 1.0));
  return checker(lon * 12, lat * 6) ? c * 0.9 : lerp(c, Vec3{1, 1, 1}, 0.6);
}

Vec3 box_albedo(int axis, int sign, double u, double v) {
  static const Vec3 kFace[6] = {{0.85, 0.20, 0.20}, {0.20, 0.75, 0.25}, {0.95, 0.85, 0.20},
                                {0.20, 0.35, 0.85}, {0.80, 0.30, 0.80}, {0.20, 0.80, 0.80}};
  const Vec3 face = kFace[2 * axis + (sign > 0 ? 1 : 0)];
  // A white border and a diagonal stripe make each face's orientation visible.
  if (std::abs(u) > 0.8 || std::abs(v) > 0.8) return {0.95, 0.95, 0.95};
  return std::fmod(std::abs(u + v + 2), 0.5) < 0.25 ? face : face * 0.55;
}

Vec3 sheet_albedo(double u, double v, bool front) {
  // Tricolour bands along u with noise-modulated stripes along v; the back is darker.
  const double band = u * 3.0;
  const Vec3 colours[3] = {{0.10, 0.30, 0.80}, {0.95, 0.95, 0.95}, {0.85, 0.15, 0.15}};
  const Vec3 base = colours[std::clamp(static_cast<int>(std::floor(band)), 0, 2)];
  const bool stripe = std::fmod(v / 0.1, 2.0) < 1.0;
  const Vec3 c = base * (stripe ? 1.0 : 0.6 + 0.3 * value_noise(u * 16, v * 8));
  return front ? c : c * 0.7;
}

}  // namespace s4d::synth
