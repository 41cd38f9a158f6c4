#include "s4d/synth/bodies.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "s4d/synth/intersect.h"

namespace s4d::synth {
namespace {

Vec3 lerp(Vec3 a, Vec3 b, double w) { return a + (b - a) * w; }

Vec3 checker_albedo(const Body& b, Vec3 local_dir) {
  if (b.checker <= 0) return b.albedo;
  const double lon = std::atan2(local_dir[2], local_dir[0]) / (2 * std::numbers::pi) + 0.5;  // [0, 1)
  const double lat = std::acos(std::clamp(local_dir[1], -1.0, 1.0)) / std::numbers::pi;      // [0, 1]
  const int u = static_cast<int>(std::floor(lon * b.checker)), v = static_cast<int>(std::floor(lat * b.checker / 2));
  return (u + v) % 2 == 0 ? b.albedo : b.albedo2;
}

BodyKey key(double t, Vec3 centre, Vec3 half) { return {t, centre, half}; }
Vec3 uniform(double r) { return {r, r, r}; }

}  // namespace

BodyKey Body::at(double t) const {
  if (keys.empty()) throw std::invalid_argument("body: no keys");
  if (t <= keys.front().t) return keys.front();
  for (size_t k = 1; k < keys.size(); ++k)
    if (t <= keys[k].t) {
      const double w = (t - keys[k - 1].t) / std::max(keys[k].t - keys[k - 1].t, 1e-12);
      return {t, lerp(keys[k - 1].centre, keys[k].centre, w), lerp(keys[k - 1].half, keys[k].half, w)};
    }
  return keys.back();
}

std::optional<BodyHit> intersect_body(const Body& body, const Ray& ray, double t, double s_min, double s_max) {
  const BodyKey k = body.at(t);
  const double angle = body.spin * t;
  const Ray local{rotate_y(ray.origin - k.centre, -angle), rotate_y(ray.dir, -angle)};
  if (body.shape == Body::Shape::box) {
    const auto h = intersect_box(local, k.half, s_min, s_max);
    if (!h) return std::nullopt;
    const Vec3 n{h->axis == 0 ? h->sign : 0.0, h->axis == 1 ? h->sign : 0.0, h->axis == 2 ? h->sign : 0.0};
    const Vec3 lp = local.at(h->s);
    const int ua = (h->axis + 1) % 3, va = (h->axis + 2) % 3;
    // A 2x2 checker per face, so the box's turn is visible.
    const bool odd = (lp[ua] > 0) != (lp[va] > 0);
    return BodyHit{h->s, rotate_y(n, angle), odd && body.checker > 0 ? body.albedo2 : body.albedo};
  }
  // Ellipsoid: the unit sphere in coordinates divided by the radii; s stays the ray's parameter.
  const Vec3 inv{1 / k.half[0], 1 / k.half[1], 1 / k.half[2]};
  const Vec3 o = mul(local.origin, inv), d = mul(local.dir, inv);
  const double a = dot(d, d), b = dot(o, d), c = dot(o, o) - 1;
  const double disc = b * b - a * c;
  if (disc < 0) return std::nullopt;
  const double root = std::sqrt(disc);
  for (const double s : {(-b - root) / a, (-b + root) / a}) {
    if (!(s > s_min && s < s_max)) continue;
    const Vec3 unit = o + d * s;  // on the unit sphere
    const Vec3 n = normalize(mul(unit, inv));
    return BodyHit{s, rotate_y(n, angle), checker_albedo(body, unit)};
  }
  return std::nullopt;
}

const std::vector<std::string>& motion_names() {
  static const std::vector<std::string> names{"bounce", "squash", "orbit"};
  return names;
}

std::vector<Body> motion_bodies(const std::string& name) {
  std::vector<Body> out;
  if (name == "bounce") {
    // Three spheres of radius 0.2 touch near the centre at t = 0.5 (centres 1.2 r from it, 2.08 r
    // apart) and fly apart, each also bouncing
    // once off an invisible floor: about two radii of travel per frame at 24 frames.
    const double r = 0.2;
    const Vec3 colours[3] = {{0.9, 0.15, 0.1}, {0.1, 0.75, 0.2}, {0.15, 0.3, 0.95}};
    for (int i = 0; i < 3; ++i) {
      const double a = 2 * std::numbers::pi * i / 3;
      const Vec3 dir{std::cos(a), 0, std::sin(a)};
      const Vec3 out_dir = rotate_y(dir, 0.9);  // they leave on other lines than they came
      Body b;
      b.albedo = colours[i];
      b.keys = {key(0.0, dir * 1.1 + Vec3{0, 0.5, 0}, uniform(r)), key(0.25, dir * 0.6 + Vec3{0, -0.3, 0}, uniform(r)),
                key(0.5, dir * (r * 1.2), uniform(r)), key(0.75, out_dir * 0.6 + Vec3{0, 0.4, 0}, uniform(r)),
                key(1.0, out_dir * 1.1 + Vec3{0, -0.3, 0}, uniform(r))};
      out.push_back(b);
    }
  } else if (name == "squash") {
    Body box;
    box.shape = Body::Shape::box;
    box.albedo = {0.85, 0.7, 0.2}, box.albedo2 = {0.45, 0.3, 0.1}, box.checker = 1;
    box.keys = {key(0.0, {0, -0.45, 0}, {0.35, 0.25, 0.35})};
    Body ball;
    ball.albedo = {0.2, 0.55, 0.9}, ball.albedo2 = {0.9, 0.9, 0.95}, ball.checker = 6;
    // Falls onto the box's top (y = -0.2), flattens to 45 % of its height while widening, rebounds.
    ball.keys = {key(0.0, {0.1, 0.8, 0.0}, uniform(0.3)), key(0.4, {0.0, 0.1, 0.0}, uniform(0.3)),
                 key(0.5, {0.0, -0.065, 0.0}, {0.42, 0.135, 0.42}), key(0.6, {0.0, 0.1, 0.0}, uniform(0.3)),
                 key(1.0, {-0.1, 0.8, 0.1}, uniform(0.3))};
    ball.spin = std::numbers::pi / 2;
    out = {box, ball};
  } else if (name == "orbit") {
    Body ball;
    ball.albedo = {0.95, 0.95, 0.9}, ball.albedo2 = {0.1, 0.1, 0.15}, ball.checker = 16;
    ball.spin = 4 * std::numbers::pi;
    constexpr int kKeys = 33;  // a circle of radius 0.75 as 32 chords, one full turn over [0, 1]
    for (int k = 0; k < kKeys; ++k) {
      const double t = double(k) / (kKeys - 1), a = 2 * std::numbers::pi * t;
      ball.keys.push_back(key(t, {0.75 * std::cos(a), 0.15 * std::sin(2 * a), 0.75 * std::sin(a)}, uniform(0.28)));
    }
    out = {ball};
  } else {
    std::string choices;
    for (const std::string& n : motion_names()) choices += (choices.empty() ? "" : ", ") + n;
    throw std::invalid_argument("--motion: unknown fixture '" + name + "' (" + choices + ")");
  }
  return out;
}

}  // namespace s4d::synth
