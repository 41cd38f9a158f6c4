// The object fixtures (`synth --dnerf --motion NAME`): small, fast, deforming and several moving
// objects on a transparent sky, cameras at three distances, a random init cloud. The layout is read
// back against D-NeRF's public conventions (transforms_*.json with camera_angle_x, per-frame time
// and an OpenGL camera-to-world matrix; RGBA frames; fused.ply), independently of the writer.
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>

#include <nlohmann/json.hpp>

#include "synth_dirs.h"
#include "s4d/data/dataset.h"
#include "s4d/io/image_io.h"
#include "s4d/synth/bodies.h"
#include "s4d/synth/dataset.h"

namespace fs = std::filesystem;
using namespace s4d;
using namespace s4d::synth;

namespace {

using s4d::synth::test::fresh;

nlohmann::json read_json(const fs::path& p) {
  std::ifstream in(p);
  return nlohmann::json::parse(in);
}

}  // namespace

TEST_CASE("motion fixtures: every body moves between frames, the squash deforms, unknown names are refused") {
  for (const std::string& name : motion_names()) {
    const std::vector<Body> bodies = motion_bodies(name);
    REQUIRE(!bodies.empty());
    bool moves = false;
    for (const Body& b : bodies) moves = moves || norm(b.at(0.5).centre - b.at(0.0).centre) > 0.3;
    CHECK_MESSAGE(moves, name);
  }
  const Body ball = motion_bodies("squash")[1];
  CHECK(ball.at(0.5).half[1] == doctest::Approx(0.135));
  CHECK(ball.at(0.5).half[0] == doctest::Approx(0.42));
  CHECK(ball.at(0.45).half[1] == doctest::Approx(0.5 * (0.3 + 0.135)));  // halfway between keys
  // The three spheres of "bounce" touch at t = 0.5 and never overlap elsewhere (a collision, not a merge).
  const std::vector<Body> balls = motion_bodies("bounce");
  for (double t = 0; t <= 1.0; t += 0.05)
    for (size_t i = 0; i < 3; ++i)
      for (size_t j = i + 1; j < 3; ++j)
        CHECK(norm(balls[i].at(t).centre - balls[j].at(t).centre) >= 2 * 0.2 - 1e-9);
  CHECK_THROWS_WITH_AS(motion_bodies("spin"), "--motion: unknown fixture 'spin' (bounce, squash, orbit)", std::invalid_argument);
}

TEST_CASE("an ellipsoid body is hit where its implicit equation says") {
  Body b;
  b.keys = {{0.0, {0, 0, 0}, {2.0, 0.5, 1.0}}};
  // Along -z from z = 5 through (x, y): the surface's z solves x^2/4 + y^2/0.25 + z^2 = 1.
  for (const auto& [x, y] : {std::pair{0.0, 0.0}, {1.0, 0.2}, {-1.5, -0.1}}) {
    const auto hit = intersect_body(b, Ray{{x, y, 5}, {0, 0, -1}}, 0.0, 1e-6, 1e30);
    REQUIRE(hit);
    const double z = std::sqrt(1 - x * x / 4 - y * y / 0.25);
    CHECK(5 - hit->s == doctest::Approx(z).epsilon(1e-9));
    CHECK(hit->normal[2] > 0);
  }
  CHECK_FALSE(intersect_body(b, Ray{{2.1, 0, 5}, {0, 0, -1}}, 0.0, 1e-6, 1e30));
}

TEST_CASE("a D-NeRF fixture: monocular train split, RGBA with a transparent sky, three focal lengths, fused.ply") {
  const fs::path dir = fresh("bounce");
  SynthOptions o;
  o.cams = 7, o.frames = 6, o.width = 48, o.height = 48, o.points = 100;
  o.dnerf = true, o.motion = "bounce", o.rgba = true, o.mixed_distances = true, o.random_init = 500;
  write_dataset(dir, o);
  for (const char* f : {"transforms_train.json", "transforms_test.json", "fused.ply", "scene.json", "train/r_005.png"})
    CHECK_MESSAGE(fs::exists(dir / f), f);
  CHECK_FALSE(fs::exists(dir / "points3D.ply"));  // the loader would prefer it to the random cloud

  const nlohmann::json train = read_json(dir / "transforms_train.json");
  REQUIRE(train["frames"].size() == 6);
  std::set<double> focal_angles, times;
  std::set<std::string> poses;
  for (const nlohmann::json& f : train["frames"]) {
    focal_angles.insert(std::round(f["camera_angle_x"].get<double>() * 1e6));
    times.insert(f["time"].get<double>());
    poses.insert(f["transform_matrix"].dump());
    // OpenGL camera-to-world: the camera looks along -z of its matrix, towards the objects at the origin.
    const auto& m = f["transform_matrix"];
    const double cx = m[0][3], cy = m[1][3], cz = m[2][3];
    const double back_dot_centre = m[0][2].get<double>() * cx + m[1][2].get<double>() * cy + m[2][2].get<double>() * cz;
    CHECK(back_dot_centre > 0);  // -back . (origin - centre) > 0: the origin is in front
  }
  CHECK(times.size() == 6);     // one view per time
  CHECK(poses.size() == 6);     // each from another place
  CHECK(focal_angles.size() == 3);
  CHECK(train["camera_angle_x"].is_number());

  // RGBA: the sky is transparent, the objects opaque; straight colour where covered.
  const s4d::io::ImageF png = s4d::io::read_png(dir / "train" / "r_000.png");
  REQUIRE(png.channels == 4);
  size_t clear = 0, opaque = 0;
  for (size_t p = 0; p < png.data.size() / 4; ++p) {
    clear += png.data[p * 4 + 3] == 0.0f;
    opaque += png.data[p * 4 + 3] == 1.0f;
  }
  CHECK(clear > png.data.size() / 4 / 2);  // mostly sky: small objects
  CHECK(opaque > 10);

  // Through the loader: white background (D-NeRF's), the random cloud as the initialisation.
  const s4d::data::Dataset d = s4d::data::load_dataset(dir);
  CHECK(d.layout == "dnerf");
  CHECK(d.background == std::array<float, 3>{1, 1, 1});
  CHECK(d.points.size() == 500 * 3);
  CHECK(d.points_file.filename() == "fused.ply");
  for (float v : d.points) CHECK((v >= -1.3f && v <= 1.3f));
}

TEST_CASE("fixture options that cannot hold are refused") {
  SynthOptions o;
  o.rgba = true;
  CHECK_THROWS_WITH_AS(check_options(o), "--rgba needs --dnerf (the DyNeRF layout's frames are RGB)", std::invalid_argument);
  o.rgba = false, o.motion = "nope";
  CHECK_THROWS_AS(check_options(o), std::invalid_argument);
  o.motion = "", o.random_init = -1;
  CHECK_THROWS_AS(check_options(o), std::invalid_argument);
}
