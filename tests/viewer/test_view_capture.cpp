// `style4d view RUN --screenshot` of a static run: the headless capture (no window, no GLFW, no
// display) equals the offline renderer's image of the same camera, is the same at two times, and an
// incomplete run or a bad request fails with a message saying what is wrong. The moving scene (a
// 4DGS run) is checked in test_view_capture_4d.cpp.
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <sstream>
#include <vector>

#include "max_abs_diff.h"
#include "s4d/io/image_io.h"
#include "s4d/io/nerf_cameras.h"
#include "s4d/scene/trained_run.h"
#include "s4d/viewer/dataset_cameras.h"
#include "view_fixture.h"

namespace fs = std::filesystem;
using s4d::test::read_text;
using s4d::test::run_style4d;
using s4d::test::max_abs_diff;

TEST_CASE("a headless capture matches the offline renderer's image of the same camera") {
  const fs::path run = s4d::test::trained_run();
  const fs::path dir = s4d::test::fresh_dir("view_capture_match");
  const s4d::scene::TrainedRun trained = s4d::scene::read_trained_run(run);
  const std::vector<s4d::io::CameraView> cameras = s4d::viewer::dataset_cameras(trained.dataset);
  const std::array<float, 3>& background = trained.dataset.background;
  REQUIRE(cameras.size() == 4);
  for (size_t cam : {size_t{0}, size_t{2}}) {
    const fs::path shot = dir / ("capture_" + std::to_string(cam) + ".png");
    const std::string args = run.string() + " --screenshot " + shot.string() + " --camera " + std::to_string(cam);
    REQUIRE_MESSAGE(run_style4d("view", args, dir / "view.log") == 0, read_text(dir / "view.log"));
    CHECK_MESSAGE(read_text(dir / "view.log").find("validation error") == std::string::npos, read_text(dir / "view.log"));

    s4d::io::CameraView view = cameras[cam];
    view.file_path = "./cam";
    s4d::io::write_nerf_cameras(dir / "transforms.json", {view});
    std::ostringstream bg;
    bg << background[0] << "," << background[1] << "," << background[2];
    const fs::path out = dir / ("render_" + std::to_string(cam));
    REQUIRE_MESSAGE(run_style4d("render", "--ply " + (run / "geometry" / "gaussians.ply").string() + " --cameras " +
                                              (dir / "transforms.json").string() + " --out " + out.string() +
                                              " --background " + bg.str(),
                                dir / "render.log") == 0,
                    read_text(dir / "render.log"));
    const s4d::io::ImageF captured = s4d::io::read_png(shot), offline = s4d::io::read_png(out / "cam.png");
    CHECK(captured.width == 64);
    CHECK(captured.height == 48);
    // Both quantise the same float image: present_pack in float, write_png in double, so a value
    // within float rounding of a level boundary may land one level apart. Measured worst case on
    // lavapipe (Mesa 22.3.6, LLVM 15): 0 levels; allowed: 1 level.
    CHECK(max_abs_diff(captured, offline) <= 1.0f / 255.0f + 1e-6f);
  }
}

TEST_CASE("captures at two times of the static scene are identical") {
  // A static run looks the same at every time; the 4DGS counterpart (captures follow the scene's
  // motion) is in test_view_capture_4d.cpp.
  const fs::path run = s4d::test::trained_run();
  const fs::path dir = s4d::test::fresh_dir("view_capture_times");
  for (const char* t : {"0", "0.75"}) {
    const std::string args = run.string() + " --screenshot " + (dir / (std::string("t") + t + ".png")).string() +
                             " --camera 1 --time " + t;
    REQUIRE_MESSAGE(run_style4d("view", args, dir / "view.log") == 0, read_text(dir / "view.log"));
  }
  CHECK(max_abs_diff(s4d::io::read_png(dir / "t0.png"), s4d::io::read_png(dir / "t0.75.png")) == 0.0f);
}

TEST_CASE("an incomplete run directory names what is missing") {
  const fs::path run = s4d::test::trained_run();
  const fs::path dir = s4d::test::fresh_dir("view_incomplete");
  const fs::path partial = dir / "partial";
  fs::create_directories(partial);
  fs::copy_file(run / "run.json", partial / "run.json");
  const std::string args = partial.string() + " --screenshot " + (dir / "x.png").string();
  CHECK(run_style4d("view", args, dir / "view.log") != 0);
  const std::string log = read_text(dir / "view.log");
  CHECK(log.find("incomplete run") != std::string::npos);
  CHECK(log.find("geometry/gaussians.ply") != std::string::npos);
  CHECK(log.find("style4d train --run ") != std::string::npos);
  CHECK(!fs::exists(dir / "x.png"));

  CHECK(run_style4d("view", (dir / "nothing").string() + " --screenshot x.png", dir / "none.log") != 0);
  CHECK(read_text(dir / "none.log").find("is not a directory") != std::string::npos);
}

TEST_CASE("a capture with an unknown style, camera, time or a bad frame budget fails saying what is wrong") {
  const fs::path run = s4d::test::trained_run();
  const fs::path dir = s4d::test::fresh_dir("view_bad_request");
  const std::string base = run.string() + " --screenshot " + (dir / "x.png").string();
  CHECK(run_style4d("view", base + " --style mosaic", dir / "style.log") != 0);
  CHECK(read_text(dir / "style.log").find("it has: original") != std::string::npos);
  CHECK(run_style4d("view", base + " --camera 4", dir / "camera.log") != 0);
  CHECK(read_text(dir / "camera.log").find("cameras 0..3") != std::string::npos);
  CHECK(run_style4d("view", base + " --time 1.5", dir / "time.log") != 0);
  CHECK(read_text(dir / "time.log").find("[0, 1]") != std::string::npos);
  CHECK(run_style4d("view", base + " --frame-budget-ms -5", dir / "budget.log") != 0);
  CHECK(read_text(dir / "budget.log").find("--frame-budget-ms") != std::string::npos);
  CHECK(!fs::exists(dir / "x.png"));
}
