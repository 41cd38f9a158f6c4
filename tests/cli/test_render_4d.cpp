// `style4d render --run` of a 4DGS run: the test path reproduces the trainer's own evaluation images
// at every test frame, renders at two times differ where the scene moves, the exact flow follows
// the deformed Gaussians, and a field's resolution comes from its checkpoint.
#include <doctest/doctest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "run4d_fixture.h"
#include "s4d/io/image_io.h"
#include "s4d/run/checkpoint.h"

namespace fs = std::filesystem;
using s4d::test::max_abs_diff;
using s4d::test::read_text;
using s4d::test::run_style4d;

namespace {

// The test path of the fixture's run, rendered once: DIR/cam00/000K.png at t = K / 2.
const fs::path& test_render() {
  static const fs::path out = [] {
    const s4d::test::Run4d& r = s4d::test::run4d();
    const fs::path dir = r.root / "test_path";
    REQUIRE_MESSAGE(run_style4d("render", "--run " + r.run.string() + " --path test --out " + dir.string(),
                                r.root / "render_test.log") == 0,
                    read_text(r.root / "render_test.log"));
    return dir;
  }();
  return out;
}

std::string frame(int k) { return s4d::test::png_name("000", k); }

}  // namespace

TEST_CASE("render --path test of a 4DGS run matches the trainer's evaluation image at every test frame") {
  const s4d::test::Run4d& r = s4d::test::run4d();
  CHECK(nlohmann::json::parse(read_text(r.run / "run.json"))["stage"] == "4dgs");
  const fs::path out = test_render();
  for (int k = 0; k < 3; ++k) {
    const s4d::io::ImageF rendered = s4d::io::read_png(out / "cam00" / frame(k));
    const s4d::io::ImageF trainer = s4d::io::read_png(r.run / "eval" / ("cam00_" + frame(k)));
    // Same Gaussians, field, time, camera, SH degree and background through the same kernels, both
    // quantised to 8 bits (the eval PNG clamps in float, the protocol's in double), so a value within
    // float rounding of a level boundary may land one level apart. Measured worst case on lavapipe
    // (Mesa 22.3.6, LLVM 15): 0 levels; allowed: 1 level.
    CHECK_MESSAGE(max_abs_diff(rendered, trainer) <= 1.0f / 255.0f + 1e-6f, "frame " << k);
  }
  const nlohmann::json summary = nlohmann::json::parse(read_text(out / "render.json"));
  CHECK(summary["stage"] == "4dgs");
  CHECK(summary["scene"].get<std::string>().find("4dgs:") == 0);
}

TEST_CASE("renders of a 4DGS run at two times differ where the scene moves") {
  const s4d::test::Run4d& r = s4d::test::run4d();
  const fs::path out = test_render();
  const s4d::io::ImageF a = s4d::io::read_png(out / "cam00" / frame(0)), b = s4d::io::read_png(out / "cam00" / frame(2));
  const s4d::io::ImageF ga = s4d::io::read_png(r.data / "cam00" / frame(0)), gb = s4d::io::read_png(r.data / "cam00" / frame(2));
  // Pixels where the ground truth moves between t = 0 and t = 1 (any channel changes by more than
  // 0.1) and where it stays (no channel changes by more than 0.01).
  double moving_sum = 0, still_sum = 0;
  size_t moving = 0, still = 0;
  for (size_t p = 0; p < a.data.size() / 3; ++p) {
    float gt = 0, rendered = 0;
    for (size_t c = 0; c < 3; ++c) {
      gt = std::max(gt, std::abs(ga.data[3 * p + c] - gb.data[3 * p + c]));
      rendered = std::max(rendered, std::abs(a.data[3 * p + c] - b.data[3 * p + c]));
    }
    if (gt > 0.1f) moving_sum += rendered, ++moving;
    if (gt < 0.01f) still_sum += rendered, ++still;
  }
  REQUIRE(moving > 0);
  REQUIRE(still > 0);
  const double moving_mean = moving_sum / double(moving), still_mean = still_sum / double(still);
  MESSAGE("mean render change: " << moving_mean << " where the scene moves (" << moving << " px), " << still_mean
                                 << " where it stays (" << still << " px)");
  // After 120 fine iterations the field has learnt part of the motion. Measured on lavapipe: mean
  // change 0.0107 where the scene moves, 0.0032 where it stays (3.4x); required: half that change
  // where it moves, and at least twice the change where it stays.
  CHECK(moving_mean > 0.005);
  CHECK(moving_mean > 2 * still_mean);
}

TEST_CASE("the exact flow of a 4DGS run seen from a fixed camera is the deformed Gaussians' motion") {
  // train:cam01 keeps the camera still, so every pixel of flow comes from the means at the two
  // frames' times that the scene source gives; a static run's would be 0 everywhere.
  const s4d::test::Run4d& r = s4d::test::run4d();
  const fs::path out = r.root / "flow_fixed_camera";
  REQUIRE_MESSAGE(run_style4d("render", "--run " + r.run.string() + " --path train:cam01 --flow --out " + out.string(),
                              r.root / "render_flow.log") == 0,
                  read_text(r.root / "render_flow.log"));
  for (const char* file : {"fw_0000.exr", "bw_0000.exr", "fw_0001.exr", "bw_0001.exr"}) {
    const s4d::io::ExrImage exr = s4d::io::read_exr(out / "flow" / file);
    double largest = 0;
    for (const char* c : {"u", "v"})
      for (float value : exr.channels.at(c)) largest = std::max(largest, double(std::abs(value)));
    MESSAGE(std::string(file) << ": largest flow " << largest << " px");
    // Measured on lavapipe: 0.19 to 0.28 px per file (the field moves the Gaussians by fractions
    // of a pixel at 48x36 after 120 fine iterations); required: a quarter of the smallest.
    CHECK(largest > 0.05);
  }
}

TEST_CASE("a field's resolution is read from its checkpoint where the checkpoint holds one") {
  // As train/field_box.h leaves a run: the checkpoint holds the field's box and texels, which may
  // differ from the preset's in run.json's settings. Here run.json says 2r - 1 texels and the
  // checkpoint the r its planes have: a render that took the settings' resolution would find
  // planes of the wrong size and stop.
  const s4d::test::Run4d& r = s4d::test::run4d();
  const fs::path copy = r.root / "fitted_run";
  fs::remove_all(copy);
  fs::copy(r.run, copy, fs::copy_options::recursive);
  const fs::path file = copy / "checkpoint" / "state.s4dckpt";
  s4d::run::Checkpoint cp = s4d::run::read_checkpoint(file);
  nlohmann::json run_json = nlohmann::json::parse(read_text(copy / "run.json"));
  const auto resolution = run_json["settings"]["field_resolution"].get<std::array<uint32_t, 4>>();
  cp.meta["field_resolution"] = resolution;
  std::vector<const std::vector<float>*> trainer;
  for (const auto& a : cp.trainer) trainer.push_back(&a);
  s4d::run::write_checkpoint(file, {cp.meta, cp.cloud, trainer, cp.extra});
  for (int k = 0; k < 3; ++k) run_json["settings"]["field_resolution"][k] = 2 * resolution[k] - 1;
  std::ofstream(copy / "run.json") << run_json.dump(2);

  const fs::path out = r.root / "fitted_path";
  REQUIRE_MESSAGE(run_style4d("render", "--run " + copy.string() + " --path test --out " + out.string(), r.root / "fitted.log") == 0,
                  read_text(r.root / "fitted.log"));
  for (int k = 0; k < 3; ++k)
    CHECK_MESSAGE(max_abs_diff(s4d::io::read_png(out / "cam00" / frame(k)), s4d::io::read_png(test_render() / "cam00" / frame(k))) == 0.0f,
                  "frame " << k);
}
