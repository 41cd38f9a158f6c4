// The dataset writer on a tiny run: the DyNeRF / Neu3D files exist, poses_bounds.npy follows the
// LLFF convention exactly (read back independently of the writer's camera code), bad options and
// occupied destinations are refused with nothing written.
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "synth_dirs.h"
#include "s4d/data/npy.h"
#include "s4d/io/image_io.h"
#include "s4d/synth/dataset.h"
#include "s4d/synth/scene.h"

namespace fs = std::filesystem;
using namespace s4d;
using namespace s4d::synth;

namespace {

using s4d::synth::test::fresh;

}  // namespace

TEST_CASE("tiny dataset: files, poses_bounds.npy shape, hwf, and the LLFF rotation read back") {
  const fs::path dir = fresh("tiny");
  SynthOptions o;
  o.cams = 3, o.frames = 2, o.width = 32, o.height = 24, o.points = 300;
  write_dataset(dir, o);
  CHECK_FALSE(fs::exists(fs::path(dir) += ".partial"));
  for (const char* f : {"cam00/0000.png", "cam00/0001.png", "cam02/0001.png", "points3D.ply", "scene.json"})
    CHECK_MESSAGE(fs::exists(dir / f), f);
  CHECK_FALSE(fs::exists(dir / "cam03"));
  CHECK_FALSE(fs::exists(dir / ".style4d-synth-partial"));
  const s4d::io::ImageF png = s4d::io::read_png(dir / "cam01" / "0000.png");
  CHECK(png.width == 32);
  CHECK(png.height == 24);
  CHECK(png.channels == 3);

  const s4d::data::NpyArray pb = s4d::data::read_npy(dir / "poses_bounds.npy");
  REQUIRE(pb.shape == std::vector<size_t>{3, 17});
  const Scene scene;
  const double focal = 16 / std::tan(25 * 3.141592653589793 / 180);  // fov_x 50 degrees at W = 32
  for (size_t c = 0; c < 3; ++c) {
    const double* row = pb.values.data() + 17 * c;
    auto m = [&](int r, int col) { return row[5 * r + col]; };  // the 3x5 matrix, row-major
    CHECK(m(0, 4) == 24);  // H
    CHECK(m(1, 4) == 32);  // W
    CHECK(m(2, 4) == doctest::Approx(focal));
    // LLFF columns (down, right, back) -> OpenGL (right, up, back) = (col1, -col0, col2).
    const Vec3 right{m(0, 1), m(1, 1), m(2, 1)}, up{-m(0, 0), -m(1, 0), -m(2, 0)}, back{m(0, 2), m(1, 2), m(2, 2)};
    const Vec3 centre{m(0, 3), m(1, 3), m(2, 3)};
    CHECK(dot(cross(right, up), back) == doctest::Approx(1));  // right-handed orthonormal
    CHECK(norm(centre - scene.centre) == doctest::Approx(std::hypot(4.0, 0.6)));
    // The camera looks along -back, straight at the scene centre, with y up.
    CHECK(dot(-back, normalize(scene.centre - centre)) == doctest::Approx(1));
    CHECK(up[1] > 0.9);
    const double near = row[15], far = row[16];
    CHECK(near > 0.5);
    CHECK(near < norm(centre - scene.centre));
    CHECK(far > norm(centre - scene.centre) + 2);  // the wall is 2.5 behind the centre
    CHECK(far < 30);
  }
  // cam00 is the middle of the arc (Neu3D's centre test camera); the others follow left to right.
  CHECK(pb.values[3] == doctest::Approx(scene.centre[0]));
  CHECK(pb.values[17 + 3] < pb.values[3]);
  CHECK(pb.values[3] < pb.values[34 + 3]);

  std::ifstream ply(dir / "points3D.ply");
  std::string magic, format;
  std::getline(ply, magic);
  std::getline(ply, format);
  CHECK(magic == "ply");
  CHECK(format == "format ascii 1.0");

  // An existing dataset is never written over.
  CHECK_THROWS_WITH_AS(write_dataset(dir, o), doctest::Contains("not an empty directory"), std::invalid_argument);
  fs::remove_all(dir);
}

TEST_CASE("an interrupted run's DIR.partial is replaced, a foreign one is left alone") {
  const fs::path dir = fresh("partial");
  const fs::path partial = fs::path(dir) += ".partial";
  SynthOptions o;
  o.cams = 2, o.frames = 2, o.width = 8, o.height = 8, o.points = 10;
  fs::create_directories(partial / "cam00");
  std::ofstream(partial / ".style4d-synth-partial") << "x";
  write_dataset(dir, o);
  CHECK(fs::exists(dir / "poses_bounds.npy"));
  CHECK_FALSE(fs::exists(partial));

  const fs::path other = fresh("foreign");
  const fs::path foreign = fs::path(other) += ".partial";
  fs::create_directories(foreign);
  std::ofstream(foreign / "notes.txt") << "mine";
  CHECK_THROWS_WITH_AS(write_dataset(other, o), doctest::Contains("not made by style4d synth"), std::invalid_argument);
  CHECK(fs::exists(foreign / "notes.txt"));
  fs::remove_all(dir);
  fs::remove_all(foreign);
}

TEST_CASE("bad options are refused before anything is written") {
  const fs::path dir = fresh("bad");
  SynthOptions o;
  o.cams = 1;
  CHECK_THROWS_WITH_AS(write_dataset(dir, o), doctest::Contains("--cams"), std::invalid_argument);
  o = {};
  o.frames = 1;
  CHECK_THROWS_WITH_AS(write_dataset(dir, o), doctest::Contains("--frame-count"), std::invalid_argument);
  o = {};
  o.width = 4;
  CHECK_THROWS_AS(write_dataset(dir, o), std::invalid_argument);
  CHECK_FALSE(fs::exists(dir));
  CHECK_FALSE(fs::exists(fs::path(dir) += ".partial"));
}

TEST_CASE("file names are fixed width") {
  CHECK(camera_dir_name(0) == "cam00");
  CHECK(camera_dir_name(12) == "cam12");
  CHECK(frame_file_name(7) == "0007.png");
}
