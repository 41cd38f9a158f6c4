// The viewer's CPU parts: camera control (snap round trip, orbit, pan, zoom, fly), playback,
// camera paths written in the format `style4d render` reads, the adaptive render scale and the
// scaled camera.
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>

#include "s4d/io/nerf_cameras.h"
#include "s4d/viewer/adaptive_resolution.h"
#include "s4d/viewer/camera_control.h"
#include "s4d/viewer/camera_path.h"
#include "s4d/viewer/frame_renderer.h"
#include "s4d/viewer/playback.h"

using s4d::viewer::CameraControl;
using s4d::Vec3;

namespace {

// A camera at (0, -4, 1) looking along +y (world z up): OpenCV axes right = +x, down = -z, forward = +y.
s4d::io::CameraView test_camera() {
  s4d::io::CameraView v;
  v.name = "cam";
  v.world_to_cam = {1, 0, 0, 0, 0, 0, -1, 1, 0, 1, 0, 4, 0, 0, 0, 1};
  v.fx = 50, v.fy = 60, v.cx = 32, v.cy = 24, v.width = 64, v.height = 48;
  return v;
}

double distance(const Vec3& a, const Vec3& b) {
  return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
}

}  // namespace

TEST_CASE("snapping to a camera reproduces its pose and field of view") {
  CameraControl c({0, 0, 1}, 1.0);
  c.snap(test_camera(), 4.0);
  CHECK(distance(c.position(), {0, -4, 1}) < 1e-12);
  CHECK(distance(c.pivot(), {0, 0, 1}) < 1e-12);
  const s4d::io::CameraView v = c.view(128, 96, "x", 0.5);
  for (int k = 0; k < 16; ++k) CHECK(v.world_to_cam[k] == doctest::Approx(test_camera().world_to_cam[k]));
  CHECK(v.fy == doctest::Approx(120));  // same vertical field of view at twice the height
  CHECK(v.fx == doctest::Approx(100));
  CHECK(v.cx == doctest::Approx(64));
  CHECK(*v.time == 0.5);
}

TEST_CASE("orbit keeps the distance to the pivot and the pivot in view; zoom and pan move as told") {
  CameraControl c({0, 0, 1}, 1.0);
  c.snap(test_camera(), 4.0);
  c.orbit(0.7, 0.3);
  CHECK(distance(c.position(), c.pivot()) == doctest::Approx(4.0));
  const Vec3& f = c.axes()[2];
  const Vec3 to_pivot{(c.pivot()[0] - c.position()[0]) / 4, (c.pivot()[1] - c.position()[1]) / 4,
                      (c.pivot()[2] - c.position()[2]) / 4};
  CHECK(distance(f, to_pivot) < 1e-9);
  CameraControl level({0, 0, 1}, 1.0);
  level.snap(test_camera(), 4.0);
  level.orbit(0, std::acos(-1.0) / 2);  // straight along the up axis: refused, the view stays level
  CHECK(distance(level.axes()[2], {0, 1, 0}) < 1e-12);
  c.zoom(1);
  CHECK(distance(c.position(), c.pivot()) == doctest::Approx(3.6));
  const Vec3 before = c.pivot();
  c.pan(10, 0, 48);  // drag right: the camera moves left (against its right axis)
  const Vec3& right = c.axes()[0];
  const double moved = (c.pivot()[0] - before[0]) * right[0] + (c.pivot()[1] - before[1]) * right[1] +
                       (c.pivot()[2] - before[2]) * right[2];
  CHECK(moved == doctest::Approx(-10 * 3.6 / 60.0));
}

TEST_CASE("zero input leaves the camera bit for bit") {
  CameraControl c({0, 0, 1}, 1.0);
  c.snap(test_camera(), 4.0);
  // Off the snapped axes and distance, where re-orthonormalising or re-placing the camera rounds.
  c.orbit(0.3, 0.1);
  c.zoom(1.3);
  c.pan(3, -2, 48);
  for (int i = 0; i < 20; ++i) {
    const s4d::splat::Camera before = c.camera(64, 48);
    c.orbit(0, 0);
    c.pan(0, 0, 48);
    c.zoom(0);
    c.fly(0, 0, 0, 0.1);
    REQUIRE(c.camera(64, 48).world_to_cam == before.world_to_cam);
    c.orbit(0.05 * i, 0.01);  // the next pose
  }
}

TEST_CASE("fly moves camera and pivot along the view axes at the given speed") {
  CameraControl c({0, 0, 1}, 2.0);
  c.snap(test_camera(), 4.0);
  c.fly(1, 0, 1, 0.5);  // forward (+y) and up (+z) for half a second at 2 units/s
  CHECK(distance(c.position(), {0, -3, 2}) < 1e-12);
  CHECK(distance(c.pivot(), {0, 1, 2}) < 1e-12);
}

TEST_CASE("the rig's up direction and the median depth come from the data") {
  const Vec3 up = s4d::viewer::estimate_up({test_camera()});
  CHECK(distance(up, {0, 0, 1}) < 1e-12);
  const std::vector<float> means = {0, 0, 1, 0, 1, 1, 0, 5, 1, 0, -10, 1};  // depths 4, 5, 9, behind
  CHECK(s4d::viewer::median_depth(test_camera(), means, 1.0) == doctest::Approx(5));
  CHECK(s4d::viewer::median_depth(test_camera(), {0, -10, 1}, 1.5) == 1.5);
}

TEST_CASE("playback advances, loops or stops at the end") {
  s4d::viewer::Playback p{.time = 0.5, .playing = true, .speed = 2, .loop = true};
  p.advance(0.5, 4.0);  // 0.5 s at 2x of a 4 s clip: +0.25
  CHECK(p.time == doctest::Approx(0.75));
  p.advance(1.0, 4.0);
  CHECK(p.time == doctest::Approx(0.25));
  p.loop = false;
  p.advance(10.0, 4.0);
  CHECK(p.time == 1.0);
  CHECK(!p.playing);
  p.advance(1.0, 4.0);  // paused: no change
  CHECK(p.time == 1.0);
}

TEST_CASE("a recorded camera path reads back as NeRF cameras") {
  CameraControl c({0, 0, 1}, 1.0);
  c.snap(test_camera(), 4.0);
  s4d::viewer::CameraPath path;
  path.add(c, 64, 48, 0.0);
  c.orbit(0.2, 0);
  path.add(c, 64, 48, 0.5);
  const auto file = std::filesystem::temp_directory_path() / "s4d_viewer_path.json";
  path.write(file);
  CHECK(path.empty());
  const auto views = s4d::io::read_nerf_cameras(file);
  REQUIRE(views.size() == 2);
  CHECK(views[0].name == "path_0000");
  CHECK(views[1].name == "path_0001");
  CHECK(*views[1].time == doctest::Approx(0.5));
  for (int k = 0; k < 16; ++k) CHECK(views[0].world_to_cam[k] == doctest::Approx(test_camera().world_to_cam[k]));
  CHECK_THROWS_AS(path.write(file), std::logic_error);
}

namespace {

using s4d::viewer::AdaptiveResolution;

// A frame whose time is fixed_ms plus per_full_ms times the fraction of the pixels rendered.
double modelled_ms(double scale, double fixed_ms, double per_full_ms) { return fixed_ms + per_full_ms * scale * scale; }

}  // namespace

TEST_CASE("the adaptive scale falls to meet the budget, holds there, and is 1 when still") {
  AdaptiveResolution policy({.budget_ms = 100, .floor = 0.25});
  CHECK(policy.scale(true) == 1);
  policy.measured(400, 1);  // a full-resolution frame at 4x the budget: half each side, a step under
  CHECK(policy.scale(true) == doctest::Approx(0.4375));  // floor(16 sqrt(80 / 400)) / 16
  CHECK(policy.scale(false) == 1);
  // Frames that follow the model land inside the band: the scale holds, frame after frame.
  for (int i = 0; i < 20; ++i) policy.measured(modelled_ms(policy.scale(true), 0, 400), policy.scale(true));
  CHECK(policy.scale(true) == doctest::Approx(0.4375));
  // A refined still frame that costs what the model says changes nothing either.
  policy.measured(400, 1);
  CHECK(policy.scale(true) == doctest::Approx(0.4375));
}

TEST_CASE("with fixed costs the scale settles without oscillating, and never leaves [floor, 1]") {
  AdaptiveResolution policy({.budget_ms = 100, .floor = 0.25});
  std::vector<double> scales;
  for (int i = 0; i < 30; ++i) {
    const double s = policy.scale(true);
    scales.push_back(s);
    policy.measured(modelled_ms(s, 40, 300), s);  // 40 ms do not shrink with the scale
  }
  for (double s : scales) CHECK((s >= 0.25 && s <= 1));
  // Settled after a few frames: the last ten are one scale, and that scale meets the budget.
  for (size_t i = 20; i < scales.size(); ++i) CHECK(scales[i] == scales[19]);
  CHECK(modelled_ms(scales.back(), 40, 300) <= 100);
  // A scene too slow for the budget even at the floor stays at the floor.
  AdaptiveResolution slow({.budget_ms = 100, .floor = 0.25});
  for (int i = 0; i < 5; ++i) slow.measured(modelled_ms(slow.scale(true), 150, 1000), slow.scale(true));
  CHECK(slow.scale(true) == 0.25);
  // Fast frames climb back to full resolution.
  for (int i = 0; i < 5; ++i) slow.measured(modelled_ms(slow.scale(true), 1, 20), slow.scale(true));
  CHECK(slow.scale(true) == 1);
}

TEST_CASE("budget 0 keeps full resolution; bad options are refused") {
  AdaptiveResolution off({.budget_ms = 0, .floor = 0.25});
  off.measured(5000, 1);
  CHECK(off.scale(true) == 1);
  CHECK_THROWS_AS(AdaptiveResolution({.budget_ms = -1, .floor = 0.25}), std::invalid_argument);
  CHECK_THROWS_AS(AdaptiveResolution({.budget_ms = 100, .floor = 0}), std::invalid_argument);
  CHECK_THROWS_AS(AdaptiveResolution({.budget_ms = 100, .floor = 1.5}), std::invalid_argument);
  CHECK_THROWS_AS(AdaptiveResolution({.budget_ms = 100, .floor = 0.25, .settle_ms = -1}), std::invalid_argument);
}

TEST_CASE("the refine waits for the view to settle") {
  const AdaptiveResolution policy({.budget_ms = 100, .floor = 0.25, .settle_ms = 150});
  CHECK(!policy.refine(0));
  CHECK(!policy.refine(149.9));
  CHECK(policy.refine(150));
}

TEST_CASE("a scaled camera keeps every pixel centre on its ray") {
  s4d::splat::Camera cam;
  cam.fx = 500, cam.fy = 510, cam.cx = 320, cam.cy = 240, cam.width = 640, cam.height = 480;
  const s4d::splat::Camera same = s4d::viewer::scaled_camera(cam, 1);
  CHECK((same.width == 640 && same.fx == 500 && same.cy == 240));
  const s4d::splat::Camera q = s4d::viewer::scaled_camera(cam, 0.25);
  CHECK((q.width == 160 && q.height == 120));
  // Small pixel centre (i + 0.5) is full-size x = (i + 0.5) * 4; both see the same ray.
  const double i = 17;
  CHECK((i + 0.5 - q.cx) / q.fx == doctest::Approx(((i + 0.5) * 4 - cam.cx) / cam.fx));
  CHECK((i + 0.5 - q.cy) / q.fy == doctest::Approx(((i + 0.5) * 4 - cam.cy) / cam.fy));
  const s4d::splat::Camera odd = s4d::viewer::scaled_camera(cam, 0.3);  // 192x144
  CHECK((odd.width == 192 && odd.height == 144));
  CHECK(s4d::viewer::scaled_size(3, 0.1) == 1);
}
