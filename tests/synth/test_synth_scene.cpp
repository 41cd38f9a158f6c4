// The synthetic scene as rendered: the camera arc faces the scene centre, rendering is
// deterministic, the dynamic objects move while the static wall stays bit-identical.
#include <doctest/doctest.h>

#include <cmath>
#include <stdexcept>
#include <utility>

#include "s4d/synth/camera_rig.h"
#include "s4d/synth/render.h"
#include "s4d/synth/scene.h"

using namespace s4d;
using namespace s4d::synth;

namespace {

const float* pixel(const RenderedView& v, int x, int y) {
  return v.rgb.data() + (static_cast<size_t>(y) * static_cast<size_t>(v.width) + static_cast<size_t>(x)) * 3;
}

bool same_pixel(const RenderedView& a, const RenderedView& b, int x, int y) {
  const float *p = pixel(a, x, y), *q = pixel(b, x, y);
  return p[0] == q[0] && p[1] == q[1] && p[2] == q[2];
}

double pixel_difference(const RenderedView& a, const RenderedView& b, int x, int y) {
  const float *p = pixel(a, x, y), *q = pixel(b, x, y);
  return std::abs(p[0] - q[0]) + std::abs(p[1] - q[1]) + std::abs(p[2] - q[2]);
}

// Whether every ray through the pixel's area (corners and centre) hits `surface` at both times.
bool pixel_sees_only(const Scene& scene, const PinholeCamera& cam, int x, int y, Surface surface) {
  for (double t : {0.0, 1.0})
    for (auto [dx, dy] : {std::pair{0.0, 0.0}, {1.0, 0.0}, {0.0, 1.0}, {1.0, 1.0}, {0.5, 0.5}}) {
      const auto hit = trace(scene, cam.ray(x + dx, y + dy), t);
      if (!hit || hit->surface != surface) return false;
    }
  return true;
}

}  // namespace

TEST_CASE("camera arc: every camera has the scene centre at its image centre, at the rig distance") {
  const Scene scene;
  const ArcRig rig;
  const auto cams = arc_cameras(rig, scene.centre, 7, 160, 120);
  REQUIRE(cams.size() == 7);
  for (const PinholeCamera& c : cams) {
    const auto uv = c.project(scene.centre);
    CHECK(uv[0] == doctest::Approx(80));
    CHECK(uv[1] == doctest::Approx(60));
    CHECK(c.position[1] - scene.centre[1] == doctest::Approx(rig.height));
    CHECK(std::hypot(c.position[0] - scene.centre[0], c.position[2] - scene.centre[2]) == doctest::Approx(rig.radius));
    CHECK(std::abs(dot(c.right, c.up)) < 1e-12);
    CHECK(c.right[1] == doctest::Approx(0));  // no roll: right stays horizontal
    // The centre ray points at the scene centre.
    const Ray r = c.ray(80, 60);
    CHECK(dot(r.dir, normalize(scene.centre - c.position)) == doctest::Approx(1));
  }
  // The arc spans rig.span_deg, ordered left to right.
  const Vec3 a = cams.front().position - scene.centre, b = cams.back().position - scene.centre;
  const double span = std::acos(dot(normalize(Vec3{a[0], 0, a[2]}), normalize(Vec3{b[0], 0, b[2]})));
  CHECK(span * 180 / 3.141592653589793 == doctest::Approx(rig.span_deg));
  CHECK(cams.front().position[0] < cams.back().position[0]);
  CHECK_THROWS_AS(arc_cameras(rig, scene.centre, 1, 160, 120), std::invalid_argument);
}

TEST_CASE("rendering is deterministic: same seed, any thread count, identical; another seed differs") {
  const Scene scene;
  const auto cams = arc_cameras(ArcRig{}, scene.centre, 3, 48, 36);
  const RenderedView a = render_view(scene, cams[1], 0.4, {2, 7, 1});
  const RenderedView b = render_view(scene, cams[1], 0.4, {2, 7, 2});
  const RenderedView c = render_view(scene, cams[1], 0.4, {2, 8, 2});
  CHECK(a.rgb == b.rgb);
  CHECK(a.min_depth == b.min_depth);
  CHECK(a.rgb != c.rgb);  // the jitter moved
  CHECK(a.min_depth > 0);
  CHECK(a.min_depth < a.max_depth);
}

TEST_CASE("motion: the sphere turns, the box slides, the sheet waves; the wall does not change") {
  const Scene scene;
  const auto cams = arc_cameras(ArcRig{}, scene.centre, 3, 80, 60);
  const PinholeCamera& cam = cams[1];
  const RenderSettings st{2, 0, 0};
  const RenderedView t0 = render_view(scene, cam, 0.0, st), t1 = render_view(scene, cam, 1.0, st);

  // The sphere's centre pixel sees the sphere at both times, in a different colour.
  const auto sphere_uv = cam.project(scene.sphere_centre);
  const int sx = static_cast<int>(sphere_uv[0]), sy = static_cast<int>(sphere_uv[1]);
  REQUIRE(pixel_sees_only(scene, cam, sx, sy, Surface::sphere));
  CHECK(pixel_difference(t0, t1, sx, sy) > 0.1);

  // The box has left the pixel where its centre was at t = 0.
  const auto box_uv = cam.project(scene.box_centre(0.0));
  const int bx = static_cast<int>(box_uv[0]), by = static_cast<int>(box_uv[1]);
  REQUIRE(trace(scene, cam.ray(bx + 0.5, by + 0.5), 0.0)->surface == Surface::box);
  CHECK(trace(scene, cam.ray(bx + 0.5, by + 0.5), 1.0)->surface != Surface::box);
  CHECK(pixel_difference(t0, t1, bx, by) > 0.1);

  // The sheet's free end moves in depth.
  const Vec3 tip{1.25, 0.7, scene.sheet.depth(1.25, 0.0)};
  const Ray tip_ray{cam.position, normalize(tip - cam.position)};
  const auto h0 = trace(scene, tip_ray, 0.0), h1 = trace(scene, tip_ray, 0.5);
  REQUIRE(h0);
  REQUIRE(h1);
  CHECK(h0->surface == Surface::sheet);
  CHECK(std::abs(h0->s - h1->s) > 0.05);

  // A pixel that sees only the wall (upper left, away from every object) is bit-identical.
  const auto wall_uv = cam.project({-2.0, 1.2, scene.wall_z});
  const int wx = static_cast<int>(wall_uv[0]), wy = static_cast<int>(wall_uv[1]);
  REQUIRE(pixel_sees_only(scene, cam, wx, wy, Surface::wall));
  CHECK(same_pixel(t0, t1, wx, wy));
}
