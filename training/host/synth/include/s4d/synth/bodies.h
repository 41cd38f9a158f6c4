// Moving bodies of the object fixtures (`synth --object --motion NAME`): small spheres, ellipsoids
// and boxes that follow keyframed paths, for captures where what moves is small, fast, deforming
// or several (the cases a monocular 4D capture loses first). Each key holds the centre and the
// half extents (an ellipsoid's radii), interpolated linearly between keys, so a squash is a change
// of half extents and a collision a sharp turn of the path.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "s4d/synth/ray.h"

namespace s4d::synth {

struct BodyKey {
  double t = 0;
  Vec3 centre{}, half{};
};

struct Body {
  enum class Shape { ellipsoid, box };
  Shape shape = Shape::ellipsoid;
  std::vector<BodyKey> keys;  // time-ordered, at least one
  Vec3 albedo{0.8, 0.8, 0.8};
  Vec3 albedo2{0.1, 0.1, 0.1};  // the checker's other colour
  int checker = 0;              // squares around the equator (ellipsoids); 0: plain
  double spin = 0;              // radians about +y over t in [0, 1]

  BodyKey at(double t) const;  // the interpolated key (t clamped to the keys' range)
};

struct BodyHit {
  double s = 0;
  Vec3 normal{}, albedo{};
};

// Nearest hit of `body` at time t with s in (s_min, s_max).
std::optional<BodyHit> intersect_body(const Body& body, const Ray& ray, double t, double s_min, double s_max);

// The named fixtures: "bounce" (three small spheres that collide and bounce apart, fast), "squash"
// (a sphere falls on a still box, squashes and rebounds), "orbit" (a finely checkered sphere on a
// full orbit, spinning). std::invalid_argument naming --motion and the choices otherwise.
std::vector<Body> motion_bodies(const std::string& name);
const std::vector<std::string>& motion_names();

}  // namespace s4d::synth
