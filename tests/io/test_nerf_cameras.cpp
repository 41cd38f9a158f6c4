// NeRF-style transforms.json: axis conversion, intrinsics resolution, errors, writer round trip.
#include <doctest/doctest.h>

#include <array>
#include <cmath>
#include <random>
#include <string>

#include "io_test_util.h"
#include "s4d/io/nerf_cameras.h"

using s4d::io::CameraView;
using s4d::test::error_at;
using s4d::test::TempDir;

namespace {

const char* kIdentity = "[[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]";

// Pixel and depth of world point p seen by view v, through world_to_cam and the intrinsics.
std::array<double, 3> project(const CameraView& v, const std::array<double, 3>& p) {
  std::array<double, 3> c{};
  for (size_t i = 0; i < 3; ++i) {
    const double* row = &v.world_to_cam[i * 4];
    c[i] = row[0] * p[0] + row[1] * p[1] + row[2] * p[2] + row[3];
  }
  return {v.fx * c[0] / c[2] + v.cx, v.fy * c[1] / c[2] + v.cy, c[2]};
}

std::vector<CameraView> read_json(const TempDir& dir, const std::string& json,
                                  std::optional<std::pair<int, int>> default_size = {}) {
  const auto path = dir / "transforms.json";
  s4d::test::write_raw(path, json);
  return s4d::io::read_nerf_cameras(path, default_size);
}

void check_read_fails(const std::string& json, const std::string& expected) {
  TempDir dir("cameras_errors");
  const auto path = dir / "transforms.json";
  s4d::test::write_raw(path, json);
  CHECK_THROWS_WITH_AS(s4d::io::read_nerf_cameras(path), error_at(path, expected), std::runtime_error);
}

std::string one_frame(const std::string& globals, const std::string& frame) {
  return "{" + globals + (globals.empty() ? "" : ", ") + "\"frames\": [{\"file_path\": \"./test/r_000\", " + frame +
         "}]}";
}

}  // namespace

TEST_CASE("an identity OpenGL camera becomes diag(1, -1, -1, 1) in OpenCV axes") {
  TempDir dir("cameras_identity");
  const double angle = 0.6911112070083618;  // Blender synthetic scenes
  const auto views = read_json(dir, one_frame("\"camera_angle_x\": 0.6911112070083618, \"w\": 800, \"h\": 600",
                                              std::string("\"transform_matrix\": ") + kIdentity));
  REQUIRE(views.size() == 1);
  const CameraView& v = views[0];
  CHECK(v.name == "r_000");
  CHECK(v.file_path == "./test/r_000");
  // Sign flips and sums of exact zeros: the result is exact.
  const std::array<double, 16> expected = {1, 0, 0, 0, 0, -1, 0, 0, 0, 0, -1, 0, 0, 0, 0, 1};
  CHECK(v.world_to_cam == expected);
  // Same formula as the reader; only the order of roundings may differ.
  CHECK(v.fx == doctest::Approx(800 / (2 * std::tan(angle / 2))).epsilon(1e-12));
  CHECK(v.fy == v.fx);
  CHECK(v.cx == 400.0);
  CHECK(v.cy == 300.0);
  CHECK(v.width == 800);
  CHECK(v.height == 600);
  CHECK_FALSE(v.time.has_value());
}

TEST_CASE("a camera at z = 5 looking at the origin sees it at the image centre, depth 5") {
  TempDir dir("cameras_project");
  const auto views = read_json(dir, one_frame("\"fl_x\": 500, \"w\": 640, \"h\": 480",
                                              "\"transform_matrix\": [[1,0,0,0],[0,1,0,0],[0,0,1,5],[0,0,0,1]]"));
  REQUIRE(views.size() == 1);
  // Each check is a handful of double operations on small exact inputs: 1e-12 is ~1e4 ulps.
  const auto origin = project(views[0], {0, 0, 0});
  CHECK(origin[0] == doctest::Approx(320).epsilon(1e-12));
  CHECK(origin[1] == doctest::Approx(240).epsilon(1e-12));
  CHECK(origin[2] == doctest::Approx(5).epsilon(1e-12));
  // World +x is image right; world +y (up in OpenGL) is image up, i.e. smaller v.
  const auto right = project(views[0], {1, 0, 0});
  CHECK(right[0] == doctest::Approx(320 + 500.0 / 5).epsilon(1e-12));
  const auto up = project(views[0], {0, 1, 0});
  CHECK(up[1] == doctest::Approx(240 - 500.0 / 5).epsilon(1e-12));
}

TEST_CASE("per-frame intrinsics override the global ones") {
  TempDir dir("cameras_override");
  const auto views =
      read_json(dir, std::string("{\"fl_x\": 500, \"fl_y\": 510, \"cx\": 300, \"w\": 640, \"h\": 480, ") +
                         "\"frames\": [{\"file_path\": \"a.png\", \"transform_matrix\": " + kIdentity + "}, " +
                         "{\"file_path\": \"b.png\", \"fl_x\": 700, \"cx\": 290, \"cy\": 200, " +
                         "\"camera_angle_x\": 1.0, \"transform_matrix\": " + kIdentity + "}]}");
  REQUIRE(views.size() == 2);
  // Values copied from the file without arithmetic: exact.
  CHECK(views[0].name == "a");
  CHECK(views[0].fx == 500.0);
  CHECK(views[0].fy == 510.0);
  CHECK(views[0].cx == 300.0);
  CHECK(views[0].cy == 240.0);
  CHECK(views[1].name == "b");
  CHECK(views[1].fx == 700.0);  // fl_x wins over camera_angle_x at the same level
  CHECK(views[1].fy == 510.0);
  CHECK(views[1].cx == 290.0);
  CHECK(views[1].cy == 200.0);
}

TEST_CASE("D-NeRF files take the size from the caller and read per-frame time") {
  TempDir dir("cameras_dnerf");
  const auto views = read_json(
      dir, one_frame("\"camera_angle_x\": 0.5", std::string("\"time\": 0.25, ") + "\"transform_matrix\": " + kIdentity),
      std::pair{400, 300});
  REQUIRE(views.size() == 1);
  CHECK(views[0].width == 400);
  CHECK(views[0].height == 300);
  REQUIRE(views[0].time.has_value());
  CHECK(*views[0].time == 0.25);  // exact in binary and copied as is
  // Same formula as the reader; only the order of roundings may differ.
  CHECK(views[0].fx == doctest::Approx(400 / (2 * std::tan(0.25))).epsilon(1e-12));
}

TEST_CASE("camera file errors name the file, the frame and the field") {
  const std::string m = std::string("\"transform_matrix\": ") + kIdentity;
  const std::string g = "\"camera_angle_x\": 0.7, \"w\": 8, \"h\": 8";
  check_read_fails("{\"camera_angle_x\": 0.7}", "missing 'frames'");
  check_read_fails("{\"frames\": []}", "'frames' is empty");
  check_read_fails(one_frame(g, "\"transform_matrix\": [[1,0,0,0],[0,1,0,0],[0,0,1,0]]"),
                   "frames[0].transform_matrix: expected 4x4 numbers");
  check_read_fails(one_frame(g, "\"transform_matrix\": [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,\"1\"]]"),
                   "frames[0].transform_matrix: expected 4x4 numbers");
  check_read_fails(one_frame(g, "\"transform_matrix\": [[2,0,0,0],[0,2,0,0],[0,0,2,0],[0,0,0,1]]"),
                   "frames[0].transform_matrix: the 3x3 part is not a rotation");
  check_read_fails(one_frame(g, "\"transform_matrix\": [[-1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]"),
                   "frames[0].transform_matrix: the 3x3 part is not a rotation");
  check_read_fails(one_frame(g, "\"transform_matrix\": [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,1,1]]"),
                   "frames[0].transform_matrix: last row is not 0 0 0 1");
  check_read_fails(one_frame("\"w\": 8, \"h\": 8", m), "frames[0]: no focal length: give camera_angle_x or fl_x");
  check_read_fails(one_frame("\"camera_angle_x\": 0.7", m), "frames[0]: no image size: give 'w' and 'h'");
  check_read_fails(one_frame(g, m + ", \"w\": 0"), "frames[0].w: expected a positive integer, got 0");
  check_read_fails(one_frame(g, m + ", \"fl_x\": -3"), "frames[0].fl_x: focal length must be positive");
  check_read_fails(one_frame(g, m + ", \"camera_angle_x\": 4"),
                   "frames[0].camera_angle_x: expected an angle in (0, pi)");
  check_read_fails(one_frame(g, m + ", \"time\": 1.5"), "frames[0].time: expected a time in [0, 1], got 1.5");
  check_read_fails(one_frame(g, m + ", \"cx\": \"4\""), "frames[0].cx: expected a number");
  check_read_fails(one_frame(g, "\"transform_matrix\": [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]], \"cy\": NaN"),
                   "malformed JSON: parse error at line 1");
  check_read_fails(one_frame(g, m + ", \"cy\": 1e999"), "malformed JSON: number overflow parsing '1e999'");
  check_read_fails("{\"frames\": [\n{\"file_path\": ]}", "malformed JSON: parse error at line 2, column 15");
  check_read_fails(
      "{" + g + ", \"frames\": [{\"file_path\": \"a/r_0.png\", " + m + "}, {\"file_path\": \"b/r_0\", " + m + "}]}",
      "frames[1]: name 'r_0' (from file_path 'b/r_0') is already used by frames[0]");
  check_read_fails("{" + g + ", \"frames\": [{" + m + "}]}", "frames[0]: missing 'file_path'");
}

TEST_CASE("camera files round-trip through the writer") {
  TempDir dir("cameras_round_trip");
  std::mt19937 rng(11);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<CameraView> in;
  for (int k = 0; k < 4; ++k) {
    CameraView v;
    v.file_path = "./train/r_" + std::to_string(k);
    v.name = "r_" + std::to_string(k);
    // Rotation from a random unit quaternion, translation up to a few units.
    double q[4];
    double norm = 0;
    for (double& x : q) {
      x = normal(rng);
      norm += x * x;
    }
    for (double& x : q) x /= std::sqrt(norm);
    const double w = q[0], x = q[1], y = q[2], z = q[3];
    const double r[9] = {1 - 2 * (y * y + z * z), 2 * (x * y - w * z),     2 * (x * z + w * y),
                         2 * (x * y + w * z),     1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
                         2 * (x * z - w * y),     2 * (y * z + w * x),     1 - 2 * (x * x + y * y)};
    for (size_t i = 0; i < 3; ++i) {
      for (size_t j = 0; j < 3; ++j) v.world_to_cam[i * 4 + j] = r[i * 3 + j];
      v.world_to_cam[i * 4 + 3] = 3 * normal(rng);
    }
    v.world_to_cam[15] = 1;
    v.fx = 500 + 10 * k;
    v.fy = 505.25 + k;
    v.cx = 320.5;
    v.cy = 239.75 - k;
    v.width = 640;
    v.height = 480 + k;
    if (k % 2 == 0) v.time = k / 3.0;
    in.push_back(v);
  }
  const auto path = dir / "transforms.json";
  s4d::io::write_nerf_cameras(path, in);
  const auto out = s4d::io::read_nerf_cameras(path);
  REQUIRE(out.size() == in.size());
  for (size_t k = 0; k < in.size(); ++k) {
    CAPTURE(k);
    CHECK(out[k].name == in[k].name);
    CHECK(out[k].file_path == in[k].file_path);
    // JSON numbers are written with enough digits to read back the same double.
    CHECK(out[k].fx == in[k].fx);
    CHECK(out[k].fy == in[k].fy);
    CHECK(out[k].cx == in[k].cx);
    CHECK(out[k].cy == in[k].cy);
    CHECK(out[k].width == in[k].width);
    CHECK(out[k].height == in[k].height);
    CHECK(out[k].time == in[k].time);
    // The matrix is inverted on write and again on read: a few roundings on values of size <= ~5.
    for (size_t e = 0; e < 16; ++e)
      CHECK(out[k].world_to_cam[e] == doctest::Approx(in[k].world_to_cam[e]).epsilon(1e-12).scale(1.0));
  }
}
