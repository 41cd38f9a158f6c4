// The built-in dynamic scene (world units are metres, y up, centred near the origin): a static
// textured wall and floor, a sphere spinning about its vertical axis, a box sliding along a
// horizontal arc while turning to follow it, and a waving flag-like sheet. Time t runs over [0, 1].
#pragma once
#include <numbers>
#include <optional>

#include <vector>

#include "s4d/synth/bodies.h"
#include "s4d/synth/ray.h"
#include "s4d/synth/wave_sheet.h"

namespace s4d::synth {

enum class Surface { wall, floor, sphere, box, sheet, body };

struct Scene {
  // Static background: wall plane z = wall_z over |x| <= half_width, floor_y <= y <= wall_top;
  // floor plane y = floor_y over |x| <= half_width, wall_z <= z <= floor_front.
  double wall_z = -2.5, floor_y = -1.0, half_width = 10.0, wall_top = 6.0, floor_front = 8.0;

  Vec3 sphere_centre{-1.1, -0.4, 0.0};  // resting on the floor
  double sphere_radius = 0.6;
  double sphere_turn = std::numbers::pi;  // radians about +y over t in [0, 1] (half a turn)

  Vec3 box_half{0.25, 0.25, 0.25};
  Vec3 box_arc_centre{0.5, -0.75, -0.3};  // y puts the box on the floor
  double box_arc_radius = 0.8;
  double box_arc_start = -std::numbers::pi / 3, box_arc_end = std::numbers::pi / 3;  // -60 to +60 degrees

  WaveSheet sheet;

  // false: the moving objects alone, on `sky`: a D-NeRF-like object capture (synth --object).
  bool room = true;
  Vec3 sky{0.55, 0.70, 0.90};  // what rays that hit nothing see
  // false: the sphere, box and sheet are left out, so only `bodies` move (synth --motion).
  bool builtin_objects = true;
  std::vector<Body> bodies;

  Vec3 light_dir = normalize(Vec3{0.35, 0.9, 0.55});  // towards the light
  double ambient = 0.3;
  // A white Blinn-Phong highlight of this strength (0: matte), so that a surface's colour depends
  // on where it is seen from (synth --glossy); a low exponent keeps it broad, as low SH degrees can fit.
  double specular = 0.0, shininess = 4.0;

  // The point every camera looks at.
  Vec3 centre{0.0, 0.0, 0.0};

  double sphere_angle(double t) const { return sphere_turn * t; }
  double box_arc_angle(double t) const { return box_arc_start + (box_arc_end - box_arc_start) * t; }
  Vec3 box_centre(double t) const;
};

struct Hit {
  double s = 0;  // ray parameter (distance, as ray directions are unit)
  Surface surface = Surface::wall;
  Vec3 point{}, normal{};  // normal faces the ray's origin
  Vec3 albedo{};
};

// Nearest hit at time t with s in (s_min, s_max).
std::optional<Hit> trace(const Scene& scene, const Ray& ray, double t, double s_min = 1e-6,
                         double s_max = 1e30);

// Lambertian shading with one directional light plus ambient (no shadows), and the scene's
// specular highlight as seen along `view_dir` (the ray's direction), in [0, 1].
Vec3 shade(const Scene& scene, const Hit& hit, const Vec3& view_dir);

// What a ray that hits nothing sees (not reached from the default cameras).
Vec3 sky_colour(const Scene& scene);

}  // namespace s4d::synth
