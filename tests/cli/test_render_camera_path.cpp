// `style4d render --run RUN --path FILE.json`: a camera path recorded by the viewer's own recorder
// (viewer::CameraPath, what R and view --record write) rendered through the 4D run and its styles:
// frame for frame what the test protocol renders from the same camera at the same times, in the
// style asked for, and moving where the path moves.
#include <doctest/doctest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "s4d/scene/trained_run.h"
#include "s4d/viewer/camera_control.h"
#include "s4d/viewer/camera_path.h"
#include "s4d/viewer/dataset_cameras.h"
#include "style_fixture.h"

using namespace s4d;
namespace fs = std::filesystem;

namespace {

// Records the fixture run's first camera (cam00, its test camera) at t = 0, 0.5 and 1, then one frame
// orbited away at t = 1, as the viewer does with its window at 48x36.
fs::path record_path(const fs::path& file) {
  const scene::TrainedRun run = scene::read_trained_run(test::run4d().run);
  const std::vector<io::CameraView> cameras = viewer::dataset_cameras(run.dataset);
  viewer::CameraControl control(viewer::estimate_up(cameras), 1.0);
  control.snap(cameras.at(0), 3.0);
  viewer::CameraPath path;
  for (double t : {0.0, 0.5, 1.0}) path.add(control, 48, 36, t);
  control.orbit(0.3, 0.0);
  path.add(control, 48, 36, 1.0);
  path.write(file);
  return file;
}

fs::path render_path(const fs::path& path, const std::string& style_args, const std::string& tag) {
  const test::Run4d& r = test::run4d();
  const fs::path out = r.root / ("path_" + tag), log = r.root / ("path_" + tag + ".log");
  fs::remove_all(out);
  REQUIRE_MESSAGE(test::run_style4d("render", "--run " + r.run.string() + " " + style_args + " --path " + path.string() +
                                                  " --out " + out.string(),
                                    log) == 0,
                  test::read_text(log));
  return out;
}

}  // namespace

TEST_CASE("a viewer-recorded camera path renders through the styled 4D run, frame for frame as the test protocol") {
  test::styled("full", "--iters 60 --mlp-iters 20 --spiral-frames 4");
  test::styled("colors", "--method colors --iters 60 --mlp-iters 0 --spiral-frames 4");
  const fs::path path = record_path(test::run4d().root / "recorded_path.json");
  const fs::path styled = render_path(path, "--style full", "full");
  // frames.json names the path and gives each frame the recorded time.
  const nlohmann::json frames = nlohmann::json::parse(test::read_text(styled / "frames.json"));
  CHECK(frames.at("path") == path.string());
  REQUIRE(frames.at("sequences").size() == 1);
  const nlohmann::json& seq = frames.at("sequences")[0];
  REQUIRE(seq.at("frames").size() == 4);
  for (size_t k = 0; k < 4; ++k) CHECK(seq.at("frames")[k].at("time") == std::min(0.5 * static_cast<double>(k), 1.0));
  // The first three frames are cam00 at the test times: as `render --path test` draws them, in the style.
  const fs::path test_frames = test::render_test_path("--style full", "full_for_path");
  for (int k = 0; k < 3; ++k) {
    CAPTURE(k);
    CHECK(test::max_abs_diff(io::read_png(styled / test::png_name("000", k)), io::read_png(test_frames / test::png_name("000", k))) <=
          1.0f / 255.0f + 1e-6f);
  }
  // Time moves the scene (0 against 1 from one camera); the orbit moves the view.
  const io::ImageF at0 = io::read_png(styled / "0000.png"), at1 = io::read_png(styled / "0002.png");
  CHECK(test::max_abs_diff(at0, at1) > 0.05f);
  CHECK(test::max_abs_diff(at1, io::read_png(styled / "0003.png")) > 0.2f);
  // The original scene along the same path is another picture; a blend of two styles renders too.
  const fs::path original = render_path(path, "", "original");
  CHECK(test::max_abs_diff(io::read_png(original / "0000.png"), at0) > 0.2f);
  const fs::path blend = render_path(path, "--style full --mix colors --alpha 0.5", "blend");
  CHECK(nlohmann::json::parse(test::read_text(blend / "render.json")).at("frames") == 4);
}

TEST_CASE("the example camera path under assets/ renders through the 4D run") {
  const fs::path example = fs::path(S4D_SOURCE_DIR) / "assets" / "paths" / "orbit.json";
  const fs::path out = render_path(example, "", "example");
  const nlohmann::json frames = nlohmann::json::parse(test::read_text(out / "frames.json"));
  const size_t count = frames.at("sequences")[0].at("frames").size();
  CHECK(count == io::read_nerf_cameras(example).size());
  char last[16];
  std::snprintf(last, sizeof last, "%04zu.png", count - 1);
  CHECK(fs::exists(out / last));
}

TEST_CASE("a camera path without times, or not a camera file, is refused naming the file and the frame") {
  const test::Run4d& r = test::run4d();
  const fs::path path = record_path(r.root / "timeless_path.json");
  nlohmann::json j = nlohmann::json::parse(test::read_text(path));
  j.at("frames")[1].erase("time");
  std::ofstream(path) << j.dump(2);
  const fs::path out = r.root / "path_timeless", log = r.root / "path_timeless.log";
  CHECK(test::exit_code(test::run_style4d("render", "--run " + r.run.string() + " --path " + path.string() + " --out " +
                                                        out.string(), log)) == 1);
  CHECK_MESSAGE(test::read_text(log).find(path.string() + ": frames[1] (path_0001): no 'time'") != std::string::npos,
                test::read_text(log));
  CHECK_FALSE(fs::exists(out));
  std::ofstream(r.root / "not_cameras.json") << "{\"frames\": 3}";
  CHECK(test::exit_code(test::run_style4d("render", "--run " + r.run.string() + " --path " + (r.root / "not_cameras.json").string() +
                                                        " --out " + out.string(), log)) == 1);
  CHECK_MESSAGE(test::read_text(log).find("not_cameras.json") != std::string::npos, test::read_text(log));
}
