// Render protocols on the host (bench/protocols): each path's sequences, frame counts and times on
// the built-in synthetic rig (forward-facing) and on a D-NeRF-like ring (surrounding), spiral cameras
// that look at the rig's centre, frames.json round trip, and path errors.
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>

#include "s4d/data/dataset.h"
#include "s4d/protocols/camera_rig.h"
#include "s4d/protocols/frames_json.h"
#include "s4d/protocols/protocol.h"
#include "s4d/synth/dataset.h"

namespace fs = std::filesystem;
using namespace s4d;
using namespace s4d::protocols;

namespace {

// The built-in scene, 4 cameras on a 75-degree arc looking at one point, 3 frames; cam00 is the test camera.
const s4d::data::Dataset& synth_dataset() {
  static const s4d::data::Dataset d = [] {
    const fs::path dir = fs::temp_directory_path() / "s4d_protocols_synth";
    fs::remove_all(dir);
    s4d::synth::SynthOptions o;
    o.cams = 4, o.frames = 3, o.width = 48, o.height = 36, o.points = 200;
    s4d::synth::write_dataset(dir, o);
    return s4d::data::load_dataset(dir);
  }();
  return d;
}

// D-NeRF-like: 12 training and 3 test views on a ring of radius 4 at height 1 around (1, 2, 0), up +z,
// each its own camera and time.
s4d::data::Dataset ring_dataset() {
  s4d::data::Dataset d;
  d.kind = "dnerf";
  d.root = "ring";
  const Vec3 centre{1, 2, 0};
  for (int k = 0; k < 15; ++k) {
    const double a = 2 * std::numbers::pi * k / 15;
    s4d::data::View v;
    v.test = k % 5 == 0;
    v.name = std::string(v.test ? "test" : "train") + "/r_" + std::to_string(k);
    v.time = k / 14.0;
    v.camera.name = "r_" + std::to_string(k);
    v.camera.world_to_cam = look_at({centre[0] + 4 * std::cos(a), centre[1] + 4 * std::sin(a), 1.0}, centre, {0, 0, 1});
    v.camera.fx = v.camera.fy = 50, v.camera.cx = 20, v.camera.cy = 15;
    v.camera.width = 40, v.camera.height = 30;
    d.views.push_back(v);
  }
  return d;
}

// Where a world point lands in a frame's image.
std::array<double, 2> project(const s4d::io::CameraView& c, const Vec3& p) {
  const auto& m = c.world_to_cam;
  double x[3];
  for (int r = 0; r < 3; ++r) x[r] = m[4 * r] * p[0] + m[4 * r + 1] * p[1] + m[4 * r + 2] * p[2] + m[4 * r + 3];
  return {c.fx * x[0] / x[2] + c.cx, c.fy * x[1] / x[2] + c.cy};
}

void check_times_are_linspace(const Sequence& s) {
  const int n = static_cast<int>(s.frames.size());
  for (int k = 0; k < n; ++k) {
    CHECK(s.frames[k].index == k);
    CHECK(s.frames[k].time == doctest::Approx(n == 1 ? 0.0 : double(k) / (n - 1)).epsilon(1e-12));
  }
}

}  // namespace

TEST_CASE("test path: the held-out camera fixed over its frame times") {
  const auto seqs = build_protocol(synth_dataset(), parse_path("test"), 0);
  REQUIRE(seqs.size() == 1);
  CHECK(seqs[0].name == "cam00");
  REQUIRE(seqs[0].frames.size() == 3);
  check_times_are_linspace(seqs[0]);  // DyNeRF time = frame / (T - 1)
  for (const ProtocolFrame& f : seqs[0].frames) CHECK(f.camera.world_to_cam == seqs[0].frames[0].camera.world_to_cam);
}

TEST_CASE("train:CAM path: that training camera over its frame times") {
  const auto seqs = build_protocol(synth_dataset(), parse_path("train:cam02"), 0);
  REQUIRE(seqs.size() == 1);
  CHECK(seqs[0].name == "cam02");
  REQUIRE(seqs[0].frames.size() == 3);
  check_times_are_linspace(seqs[0]);
  for (const s4d::data::View& v : synth_dataset().views)
    if (v.name == "cam02/0000") CHECK(v.camera.world_to_cam == seqs[0].frames[0].camera.world_to_cam);
}

TEST_CASE("the synthetic arc is forward-facing and its centre is the point the cameras look at") {
  const RigSummary rig = analyse_rig(synth_dataset());
  CHECK(rig.forward_facing);
  CHECK(rig.cameras.size() == 3);  // cam01..cam03; cam00 is the test camera
  // Every training camera looks straight at the centre: it projects to the principal point.
  for (const s4d::io::CameraView& c : rig.cameras) {
    const auto uv = project(c, rig.centre);
    // Poses pass through poses_bounds.npy in float64; measured worst case 4.3e-14 px.
    CHECK(std::abs(uv[0] - c.cx) < 1e-9);
    CHECK(std::abs(uv[1] - c.cy) < 1e-9);
  }
}

TEST_CASE("spiral frames advance time over [0, 1] and look at the rig's centre") {
  for (const s4d::data::Dataset& d : {synth_dataset(), ring_dataset()}) {
    const RigSummary rig = analyse_rig(d);
    for (int n : {1, 2, 7}) {
      const auto seqs = build_protocol(d, parse_path("spiral"), n);
      REQUIRE(seqs.size() == 1);
      REQUIRE(seqs[0].frames.size() == size_t(n));
      check_times_are_linspace(seqs[0]);
      for (const ProtocolFrame& f : seqs[0].frames) {
        const auto uv = project(f.camera, rig.centre);
        CHECK(std::abs(uv[0] - f.camera.cx) < 1e-9);  // look_at in double: rounding only
        CHECK(std::abs(uv[1] - f.camera.cy) < 1e-9);
        CHECK(f.camera.width == rig.cameras.front().width);
      }
    }
  }
}

TEST_CASE("a ring of cameras is a surrounding rig: the spiral is a helix at the ring's radius") {
  const s4d::data::Dataset d = ring_dataset();
  const RigSummary rig = analyse_rig(d);
  CHECK_FALSE(rig.forward_facing);
  CHECK(rig.centre[0] == doctest::Approx(1).epsilon(1e-9));
  CHECK(rig.centre[1] == doctest::Approx(2).epsilon(1e-9));
  CHECK(std::abs(rig.centre[2]) < 1e-9);
  const auto frames = spiral_frames(rig, 8);
  for (const ProtocolFrame& f : frames) {
    const Vec3 c = camera_centre(f.camera);
    CHECK(std::hypot(c[0] - 1, c[1] - 2) == doctest::Approx(4).epsilon(1e-9));
    CHECK(c[2] == doctest::Approx(1).epsilon(1e-9));  // every camera at height 1: a flat helix
  }
}

TEST_CASE("D-NeRF test path: each test view's camera over every test-view time") {
  const auto seqs = build_protocol(ring_dataset(), parse_path("test"), 0);
  REQUIRE(seqs.size() == 3);
  CHECK(seqs[0].name == "test_r_0");
  for (const Sequence& s : seqs) {
    REQUIRE(s.frames.size() == 3);
    CHECK(s.frames[0].time == doctest::Approx(0.0));
    CHECK(s.frames[1].time == doctest::Approx(5 / 14.0));
    CHECK(s.frames[2].time == doctest::Approx(10 / 14.0));
  }
}

TEST_CASE("bad paths are refused with the accepted forms or the camera names") {
  CHECK_THROWS_WITH_AS(parse_path("orbit"), doctest::Contains("expected test, spiral, train:CAM (a training camera name such as train:cam01) or a camera path FILE.json"), std::invalid_argument);
  CHECK_THROWS_AS(parse_path("train:"), std::invalid_argument);
  CHECK_THROWS_WITH_AS(build_protocol(synth_dataset(), parse_path("train:cam00"), 0),
                       doctest::Contains("the training cameras are cam01, cam02, cam03"), std::invalid_argument);
  CHECK_THROWS_WITH_AS(build_protocol(synth_dataset(), parse_path("train:cam9"), 0), doctest::Contains("no training camera named 'cam9'"),
                       std::invalid_argument);
  CHECK_THROWS_WITH_AS(spiral_frames(analyse_rig(synth_dataset()), 0), doctest::Contains("at least 1"), std::invalid_argument);
}

TEST_CASE("frames.json reads back every frame's index, time and camera exactly") {
  FramesRecord rec{"spiral", "png", {}};
  const auto seqs = build_protocol(synth_dataset(), parse_path("spiral"), 4);
  rec.sequences.push_back({seqs[0], ".", "", {"0000.png", "0001.png", "0002.png", "0003.png"}, true});
  const auto test = build_protocol(ring_dataset(), parse_path("test"), 0);
  rec.sequences.push_back({test[1], test[1].name, "video.mp4", {"", "", ""}, false});
  const fs::path file = fs::temp_directory_path() / "s4d_protocols_frames.json";
  write_frames_json(file, rec);
  const FramesRecord back = read_frames_json(file);
  CHECK(back.path == "spiral");
  CHECK(back.format == "png");
  REQUIRE(back.sequences.size() == 2);
  for (size_t s = 0; s < 2; ++s) {
    const SequenceRecord &a = rec.sequences[s], &b = back.sequences[s];
    CHECK(a.sequence.name == b.sequence.name);
    CHECK(a.dir == b.dir);
    CHECK(a.video == b.video);
    CHECK(a.flow == b.flow);
    CHECK(a.files == b.files);
    REQUIRE(a.sequence.frames.size() == b.sequence.frames.size());
    for (size_t k = 0; k < a.sequence.frames.size(); ++k) {
      const ProtocolFrame &x = a.sequence.frames[k], &y = b.sequence.frames[k];
      CHECK(x.index == y.index);
      CHECK(x.time == y.time);  // JSON numbers round-trip doubles exactly (shortest representation)
      CHECK(x.camera.world_to_cam == y.camera.world_to_cam);
      CHECK((x.camera.fx == y.camera.fx && x.camera.fy == y.camera.fy && x.camera.cx == y.camera.cx &&
             x.camera.cy == y.camera.cy && x.camera.width == y.camera.width && x.camera.height == y.camera.height));
    }
  }
  fs::path bad = fs::temp_directory_path() / "s4d_protocols_bad.json";
  std::ofstream(bad) << R"({"path": "test", "format": "png", "sequences": [{"name": "a", "dir": ".", "video": "", "flow": false, "frames": [{"index": 0}]}]})";
  CHECK_THROWS_WITH_AS(read_frames_json(bad), doctest::Contains("sequences[0].frames[0]: no field 'time'"), std::runtime_error);
}
