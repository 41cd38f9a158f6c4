// `style4d synth` end to end on a tiny run: exit 0 and the dataset files; bad flags exit non-zero
// with a one-line reason and leave nothing behind.
#include <doctest/doctest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "cli_run.h"
#include "s4d/data/dataset.h"

namespace fs = std::filesystem;

namespace {

int run(const std::string& args, const fs::path& log) { return s4d::test::run_style4d("synth", args, log); }
std::string read_text(const fs::path& p) { return s4d::test::read_text(p); }
fs::path fresh_dir(const std::string& name) { return s4d::test::fresh_dir("synth_" + name); }

}  // namespace

TEST_CASE("synth writes a tiny DyNeRF dataset") {
  const fs::path dir = fresh_dir("ok");
  const fs::path out = dir / "data";
  REQUIRE(run("--out " + out.string() + " --cams 3 --frames 2 --size 32x24 --seed 3", dir / "log.txt") == 0);
  for (const char* f : {"cam00/0000.png", "cam00/0001.png", "cam01/0000.png", "cam02/0001.png", "poses_bounds.npy",
                        "points3D.ply", "scene.json"})
    CHECK_MESSAGE(fs::exists(out / f), f);
  CHECK_FALSE(fs::exists(dir / "data.partial"));
  CHECK(read_text(out / "scene.json").find("\"seed\": 3") != std::string::npos);
  CHECK(read_text(dir / "log.txt").find("synth") != std::string::npos);  // progress on stderr
}

TEST_CASE("synth --video writes one mp4 per camera instead of frame folders") {
  const fs::path dir = fresh_dir("video");
  const fs::path out = dir / "data";
  REQUIRE(run("--out " + out.string() + " --cams 2 --frames 2 --size 32x24 --video", dir / "log.txt") == 0);
  for (const char* f : {"cam00.mp4", "cam01.mp4", "poses_bounds.npy", "points3D.ply", "scene.json"})
    CHECK_MESSAGE(fs::exists(out / f), f);
  CHECK_FALSE(fs::exists(out / "cam00"));
  CHECK(read_text(out / "scene.json").find("camNN.mp4") != std::string::npos);
}

TEST_CASE("synth --dnerf writes a monocular D-NeRF dataset: one training camera per time, camera 0 held out; 4DGS trains on it") {
  const fs::path dir = fresh_dir("dnerf");
  const fs::path out = dir / "data";
  REQUIRE(run("--out " + out.string() + " --dnerf --cams 4 --frames 6 --size 32x24", dir / "log.txt") == 0);
  const s4d::data::Dataset d = s4d::data::load_dataset(out);
  CHECK(d.kind == "dnerf");
  std::vector<const s4d::data::View*> train, test;
  for (const auto& v : d.views) (v.test ? test : train).push_back(&v);
  REQUIRE(train.size() == 6);
  REQUIRE(test.size() == 6);
  for (size_t k = 0; k < train.size(); ++k) {
    CHECK(train[k]->time == doctest::Approx(static_cast<double>(k) / 5.0));
    CHECK(train[k]->camera.world_to_cam != test[k]->camera.world_to_cam);  // never the test camera
    if (k > 0) CHECK(train[k]->camera.world_to_cam != train[k - 1]->camera.world_to_cam);  // the camera jumps
  }
  for (const auto* v : test) CHECK(v->camera.world_to_cam == test[0]->camera.world_to_cam);
  // Both stages run on it (monocular: every view its own camera and time).
  REQUIRE_MESSAGE(s4d::test::run_style4d("train", "--data " + out.string() + " --out " + (dir / "run").string() +
                                                      " --preset fast --iters 20 --fine-iters 20", dir / "train.log") == 0,
                  read_text(dir / "train.log"));
  CHECK(read_text(dir / "run" / "train.json").find("\"stage\": \"fine\"") != std::string::npos);
}

TEST_CASE("synth refuses bad flags with one line and writes nothing") {
  const fs::path dir = fresh_dir("bad");
  const fs::path out = dir / "data";
  for (const std::string flags : {"--cams 1", "--frame-count 1", "--size 32", "--size 4x4", "--size 32x24x1",
                                  "--cams 3x", "--seed -1", "--cams", "--size 33x24 --video"}) {
    CAPTURE(flags);
    CHECK(s4d::test::exit_code(run("--out " + out.string() + " " + flags, dir / "log.txt")) == 2);  // a usage error
    const std::string log = read_text(dir / "log.txt");
    CHECK(log.find("error") != std::string::npos);
    CHECK(std::count(log.begin(), log.end(), '\n') == 1);
    CHECK_FALSE(fs::exists(out));
  }
  CHECK(run("--cams 3", dir / "log.txt") != 0);  // --out is required
  CHECK(read_text(dir / "log.txt").find("--out") != std::string::npos);
}
