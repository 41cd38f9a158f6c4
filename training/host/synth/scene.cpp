#include "s4d/synth/scene.h"

#include <algorithm>
#include <cmath>

#include "s4d/synth/intersect.h"
#include "s4d/synth/textures.h"

namespace s4d::synth {
namespace {

Vec3 axis_vector(int axis, double sign) {
  return {axis == 0 ? sign : 0.0, axis == 1 ? sign : 0.0, axis == 2 ? sign : 0.0};
}

// Each candidate narrows s_max, so later primitives only need to beat the current nearest.
void consider_background(const Scene& sc, const Ray& ray, double s_min, double& s_max, std::optional<Hit>& best) {
  if (!sc.room) return;
  if (auto s = intersect_plane(ray, {0, 0, sc.wall_z}, {0, 0, 1}, s_min, s_max)) {
    const Vec3 p = ray.at(*s);
    if (std::abs(p[0]) <= sc.half_width && p[1] >= sc.floor_y && p[1] <= sc.wall_top) {
      s_max = *s;
      best = Hit{*s, Surface::wall, p, {0, 0, 1}, wall_albedo(p[0], p[1])};
    }
  }
  if (auto s = intersect_plane(ray, {0, sc.floor_y, 0}, {0, 1, 0}, s_min, s_max)) {
    const Vec3 p = ray.at(*s);
    if (std::abs(p[0]) <= sc.half_width && p[2] >= sc.wall_z && p[2] <= sc.floor_front) {
      s_max = *s;
      best = Hit{*s, Surface::floor, p, {0, 1, 0}, floor_albedo(p[0], p[2])};
    }
  }
}

void consider_sphere(const Scene& sc, const Ray& ray, double t, double s_min, double& s_max,
                     std::optional<Hit>& best) {
  if (auto s = intersect_sphere(ray, sc.sphere_centre, sc.sphere_radius, s_min, s_max)) {
    const Vec3 p = ray.at(*s);
    const Vec3 n = (p - sc.sphere_centre) * (1.0 / sc.sphere_radius);
    // The texture is fixed in the sphere's frame, which has turned by sphere_angle(t).
    const Vec3 local = rotate_y(n, -sc.sphere_angle(t));
    s_max = *s;
    best = Hit{*s, Surface::sphere, p, n, sphere_albedo(local)};
  }
}

void consider_box(const Scene& sc, const Ray& ray, double t, double s_min, double& s_max, std::optional<Hit>& best) {
  // The box turns with the arc so that it keeps facing along its path.
  const double angle = sc.box_arc_angle(t);
  const Vec3 centre = sc.box_centre(t);
  const Ray local{rotate_y(ray.origin - centre, -angle), rotate_y(ray.dir, -angle)};
  if (auto h = intersect_box(local, sc.box_half, s_min, s_max)) {
    const Vec3 lp = local.at(h->s);
    const int ua = (h->axis + 1) % 3, va = (h->axis + 2) % 3;
    const double u = lp[ua] / sc.box_half[ua], v = lp[va] / sc.box_half[va];
    s_max = h->s;
    best = Hit{h->s, Surface::box, ray.at(h->s), rotate_y(axis_vector(h->axis, h->sign), angle),
               box_albedo(h->axis, h->sign, u, v)};
  }
}

void consider_sheet(const Scene& sc, const Ray& ray, double t, double s_min, double& s_max, std::optional<Hit>& best) {
  if (auto s = intersect_wave_sheet(ray, sc.sheet, t, s_min, s_max)) {
    const Vec3 p = ray.at(*s);
    const WaveSheet& w = sc.sheet;
    const bool front = ray.dir[2] < 0;  // seen from +z
    s_max = *s;
    best = Hit{*s, Surface::sheet, p, w.normal(p[0], t),
               sheet_albedo((p[0] - w.x0) / (w.x1 - w.x0), (p[1] - w.y0) / (w.y1 - w.y0), front)};
  }
}

void consider_bodies(const Scene& sc, const Ray& ray, double t, double s_min, double& s_max, std::optional<Hit>& best) {
  for (const Body& b : sc.bodies)
    if (auto h = intersect_body(b, ray, t, s_min, s_max)) {
      s_max = h->s;
      best = Hit{h->s, Surface::body, ray.at(h->s), h->normal, h->albedo};
    }
}

}  // namespace

Vec3 Scene::box_centre(double t) const {
  const double a = box_arc_angle(t);
  return box_arc_centre + Vec3{std::sin(a), 0, std::cos(a)} * box_arc_radius;
}

std::optional<Hit> trace(const Scene& scene, const Ray& ray, double t, double s_min, double s_max) {
  std::optional<Hit> best;
  consider_background(scene, ray, s_min, s_max, best);
  if (scene.builtin_objects) {
    consider_sphere(scene, ray, t, s_min, s_max, best);
    consider_box(scene, ray, t, s_min, s_max, best);
    consider_sheet(scene, ray, t, s_min, s_max, best);
  }
  consider_bodies(scene, ray, t, s_min, s_max, best);
  // Two-sided surfaces: shade the side the ray sees.
  if (best && dot(best->normal, ray.dir) > 0) best->normal = -best->normal;
  return best;
}

Vec3 shade(const Scene& scene, const Hit& hit, const Vec3& view_dir) {
  const double lambert = std::max(0.0, dot(hit.normal, scene.light_dir));
  Vec3 c = hit.albedo * (scene.ambient + (1 - scene.ambient) * lambert);
  if (scene.specular > 0) {
    const Vec3 half = normalize(scene.light_dir - view_dir);
    const double highlight = scene.specular * std::pow(std::max(0.0, dot(hit.normal, half)), scene.shininess);
    c = c + Vec3{highlight, highlight, highlight};
  }
  return {std::clamp(c[0], 0.0, 1.0), std::clamp(c[1], 0.0, 1.0), std::clamp(c[2], 0.0, 1.0)};
}

Vec3 sky_colour(const Scene& scene) { return scene.sky; }

}  // namespace s4d::synth
