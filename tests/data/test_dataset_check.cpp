// check_dataset on tiny synth datasets: a clean one has no problems and the right summary; each seeded
// problem (a frame of another size, a frame that is not a PNG, a camera turned away from the scene, a
// missing D-NeRF image, times out of order, repeated or outside [0, 1], a video frame past the end,
// non-finite intrinsics, no test views) is reported with its file, field and severity.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "data_test_util.h"
#include "s4d/data/dataset_check.h"
#include "s4d/io/nerf_cameras.h"
#include "s4d/synth/dataset.h"

using namespace s4d;
namespace fs = std::filesystem;

namespace {

synth::SynthOptions tiny(bool dnerf = false, bool video = false) {
  synth::SynthOptions o;
  o.cams = 4;
  o.frames = 4;
  o.width = 32;
  o.height = 24;
  o.points = 500;
  o.dnerf = dnerf;
  o.video = video;
  return o;
}

// The problems reported at `file` and `field`.
std::vector<data::Problem> at(const data::DatasetReport& r, const fs::path& file, const std::string& field) {
  std::vector<data::Problem> out;
  for (const data::Problem& p : r.problems) {
    if (p.file == file && p.field == field) out.push_back(p);
  }
  return out;
}

std::string all(const data::DatasetReport& r) {
  std::string s;
  for (const data::Problem& p : r.problems) s += data::format_problem(p) + "\n";
  return s;
}

// One problem at file and field, of this severity, whose message contains `text`.
void check_one(const data::DatasetReport& r, const fs::path& file, const std::string& field, data::Severity severity,
               const std::string& text) {
  const std::vector<data::Problem> found = at(r, file, field);
  INFO("expected at " << file.string() << ": " << field << "; report:\n" << all(r));
  REQUIRE(found.size() == 1);
  CHECK(found[0].severity == severity);
  CHECK_MESSAGE(found[0].message.find(text) != std::string::npos, found[0].message);
}

// Turns a DyNeRF camera half round about its down axis (LLFF columns right and back negated): still a
// rotation, so the loader takes it, but it now looks away from the scene.
void turn_away_llff(const fs::path& npy, size_t row) {
  data::NpyArray a = data::read_npy(npy);
  for (size_t r = 0; r < 3; ++r) {
    a.values[row * 17 + r * 5 + 1] *= -1;
    a.values[row * 17 + r * 5 + 2] *= -1;
  }
  data::write_npy(npy, a);
}

}  // namespace

TEST_CASE("a clean DyNeRF dataset has no problems and its summary") {
  test::TempDir dir("check_clean");
  synth::write_dataset(dir / "d", tiny());
  const data::Dataset d = data::load_dataset(dir / "d");
  const data::DatasetReport r = data::check_dataset(d);
  CHECK_MESSAGE(r.problems.empty(), all(r));
  const data::DatasetSummary& s = r.summary;
  CHECK(s.layout == "dynerf-frames");
  CHECK(s.kind == "dynerf");
  CHECK(s.cameras == 4);
  CHECK(s.min_frames_per_camera == 4);
  CHECK(s.max_frames_per_camera == 4);
  CHECK(s.train_views == 12);
  CHECK(s.test_views == 4);
  REQUIRE(s.resolutions.size() == 1);
  CHECK(s.resolutions[0].width == 32);
  CHECK(s.resolutions[0].height == 24);
  CHECK(s.resolutions[0].views == 16);
  CHECK(s.time_min == 0.0);
  CHECK(s.time_max == 1.0);
  CHECK(s.train_times == 4);
  CHECK(s.train_views_per_time == doctest::Approx(3.0));
  CHECK_FALSE(s.monocular);
  CHECK(s.points_file == dir / "d" / "points3D.ply");
  CHECK(s.points == d.points.size() / 3);
  CHECK(s.points > 0);
  CHECK(s.extent == d.extent);
  REQUIRE(s.scene_centre);
  CHECK(s.scene_centre_from == "point cloud centroid");
  for (size_t a = 0; a < 3; ++a) {
    CHECK(s.centre_min[a] <= s.centre_max[a]);
    CHECK(s.points_min[a] <= (*s.scene_centre)[a]);
    CHECK((*s.scene_centre)[a] <= s.points_max[a]);
  }
  const std::string table = data::format_summary(s);
  CHECK(table.find("dynerf-frames") != std::string::npos);
  CHECK(table.find("32x24") != std::string::npos);
  const std::string json = data::to_json(r);
  CHECK(json.find("\"errors\": 0") != std::string::npos);
  CHECK(json.find("\"layout\": \"dynerf-frames\"") != std::string::npos);

  // Downscaled: the cameras are 16x12 and the 32x24 frames still match them.
  const data::DatasetReport half = data::check_dataset(data::load_dataset(dir / "d", {.downscale = 2}));
  CHECK_MESSAGE(half.problems.empty(), all(half));
  REQUIRE(half.summary.resolutions.size() == 1);
  CHECK(half.summary.resolutions[0].width == 16);
  CHECK(half.summary.resolutions[0].height == 12);

  // Without the point cloud the scene centre is where the optical axes meet, and every camera faces it.
  data::Dataset bare = d;
  bare.points.clear();
  bare.colors.clear();
  bare.points_file.clear();
  const data::DatasetReport axes = data::check_dataset(bare);
  CHECK_MESSAGE(axes.problems.empty(), all(axes));
  CHECK(axes.summary.scene_centre_from == "nearest point to the optical axes");
}

TEST_CASE("seeded DyNeRF problems: a frame of another size, frames that are not PNGs, a camera facing away") {
  test::TempDir dir("check_dynerf");
  const fs::path root = dir / "d";
  synth::write_dataset(root, tiny());
  io::write_png(root / "cam02" / "0002.png", test::pattern(40, 30, 3, 1));
  test::write_raw(root / "cam02" / "0001.png", "not a png at all, not even close");
  // A valid header on a body cut short: only decoding finds it (the loader's background probe reads
  // this frame, fails, and load_and_check loads again without the probe).
  const std::string png = test::read_raw(root / "cam01" / "0003.png");
  test::write_raw(root / "cam01" / "0003.png", png.substr(0, 40));
  turn_away_llff(root / "poses_bounds.npy", 3);
  CHECK_THROWS(data::load_dataset(root));

  const data::DatasetReport r = data::load_and_check(root).report;
  check_one(r, root / "cam02" / "0002.png", "size", data::Severity::error, "is 40x30");
  CHECK(at(r, root / "cam02" / "0002.png", "size")[0].message.find("is 32x24") != std::string::npos);
  check_one(r, root / "cam02" / "0001.png", "file", data::Severity::error, "not a PNG");
  check_one(r, root / "poses_bounds.npy", "row 3 (cam03)", data::Severity::error, "faces away from the scene");
  check_one(r, root / "cam01" / "0003.png", "pixels", data::Severity::error, "cannot be decoded");
  CHECK_MESSAGE(r.errors() == 4, all(r));
  CHECK_MESSAGE(r.warnings() == 0, all(r));

  // At downscale 2 the 40x30 frame is still the wrong size, and the message gives the range that fits.
  const data::DatasetReport half = data::load_and_check(root, {.downscale = 2}).report;
  check_one(half, root / "cam02" / "0002.png", "size", data::Severity::error, "16x12 at downscale 2, which needs 32..33 x 24..25");

  // The axes' meeting point does not move when a camera turns round on its axis: still found without points.
  data::Dataset bare = data::load_and_check(root).dataset;
  bare.points.clear();
  bare.points_file.clear();
  check_one(data::check_dataset(bare), root / "poses_bounds.npy", "row 3 (cam03)", data::Severity::error,
            "nearest point to the optical axes");
}

TEST_CASE("seeded D-NeRF problems: times out of order, a frame of another size, a view facing away; a missing image") {
  test::TempDir dir("check_dnerf");
  const fs::path root = dir / "d";
  synth::write_dataset(root, tiny(true));
  const fs::path train_json = root / "transforms_train.json";
  {
    const data::DatasetReport clean = data::check_dataset(data::load_dataset(root));
    CHECK_MESSAGE(clean.problems.empty(), all(clean));
    CHECK(clean.summary.layout == "dnerf");
    CHECK(clean.summary.cameras == 8);  // every view its own camera
    CHECK(clean.summary.train_views == 4);
    CHECK(clean.summary.test_views == 4);
    CHECK(clean.summary.monocular);
    CHECK(clean.summary.train_views_per_time == doctest::Approx(1.0));
  }
  std::vector<io::CameraView> cams = io::read_nerf_cameras(train_json, std::pair{32, 24});
  std::swap(cams[1].time, cams[2].time);  // 0, 2/3, 1/3, 1
  for (size_t i : {0, 2}) {               // half a turn about the camera's y axis: x and z rows negated
    for (size_t j = 0; j < 4; ++j) {
      cams[3].world_to_cam[i * 4 + j] *= -1;
    }
  }
  io::write_nerf_cameras(train_json, cams);
  io::write_png(root / "test" / "r_002.png", test::pattern(40, 30, 3, 2));

  const data::DatasetReport r = data::load_and_check(root).report;
  check_one(r, train_json, "frames[2].time", data::Severity::warning, "times out of order");
  check_one(r, train_json, "frames[3].transform_matrix", data::Severity::error, "faces away from the scene");
  check_one(r, root / "test" / "r_002.png", "size", data::Severity::error, "is 40x30");
  CHECK_MESSAGE(r.errors() == 2, all(r));
  CHECK_MESSAGE(r.warnings() == 1, all(r));

  // A missing image is the loader's to refuse: load_and_check throws its message (check-data exits 2).
  fs::remove(root / "train" / "r_001.png");
  CHECK_THROWS_WITH_AS(data::load_and_check(root),
                       test::error_at(train_json, "frames[1].file_path: image " + (root / "train" / "r_001.png").string() +
                                                      " does not exist"),
                       std::runtime_error);
}

TEST_CASE("times repeated, out of order or outside [0, 1] per physical camera; non-finite cameras; a missing frame") {
  test::TempDir dir("check_times");
  const fs::path root = dir / "d";
  synth::write_dataset(root, tiny());
  data::Dataset d = data::load_dataset(root);
  REQUIRE(d.views.size() == 16);  // cam00 frames 0-3, cam01 frames 0-3, ...
  d.views[6].time = d.views[5].time;             // cam01: 0, 1/3, 1/3, 1
  std::swap(d.views[9].time, d.views[10].time);  // cam02: 0, 2/3, 1/3, 1
  d.views[12].time = 1.5;                        // cam03: 1.5, 1/3, ...
  d.views[3].camera.fx = std::nan("");
  d.views[1].image = root / "cam00" / "0099.png";

  const data::DatasetReport r = data::check_dataset(d);
  const std::string frame_time = "time (from the frame order)";
  check_one(r, root / "cam01" / "0002.png", frame_time, data::Severity::error, "duplicate (camera 1, time 0.333333)");
  check_one(r, root / "cam02" / "0002.png", frame_time, data::Severity::error, "times out of order");
  check_one(r, root / "cam03" / "0000.png", frame_time, data::Severity::error, "outside [0, 1]");
  check_one(r, root / "cam03" / "0001.png", frame_time, data::Severity::error, "times out of order");
  check_one(r, root / "poses_bounds.npy", "row 0 (cam00) hwf", data::Severity::error, "non-finite");
  check_one(r, root / "cam00" / "0099.png", "file", data::Severity::error, "does not exist");
  CHECK_MESSAGE(r.errors() == 6, all(r));

  // No test views: a warning only.
  data::Dataset no_test = data::load_dataset(root);
  for (data::View& v : no_test.views) v.test = false;
  const data::DatasetReport nt = data::check_dataset(no_test);
  check_one(nt, root, "split", data::Severity::warning, "no test views");
  CHECK(nt.errors() == 0);
}

TEST_CASE("a DyNeRF video dataset: clean, then a frame past the end of its video") {
  test::TempDir dir("check_video");
  const fs::path root = dir / "d";
  synth::write_dataset(root, tiny(false, true));
  data::Dataset d = data::load_dataset(root);
  const data::DatasetReport clean = data::check_dataset(d);
  CHECK_MESSAGE(clean.problems.empty(), all(clean));
  CHECK(clean.summary.layout == "dynerf-video");
  CHECK(clean.summary.max_frames_per_camera == 4);
  d.views[5].frame_in_file = 9;
  const data::DatasetReport r = data::check_dataset(d);
  check_one(r, root / "cam01.mp4", "frame 9", data::Severity::error, "the video has 4 frames");
}
