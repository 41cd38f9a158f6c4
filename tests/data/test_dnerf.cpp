// D-NeRF loading: per-frame time, ".png" appended, RGBA composited on white, per-frame intrinsics,
// the image size as default when the file gives none, val and test held out.
#include <doctest/doctest.h>

#include "data_test_util.h"
#include "s4d/data/frame_cache.h"

using namespace s4d;

namespace {

// Camera-to-world (OpenGL) at distance 4 on +z, or rotated 90 degrees about y onto +x.
const char* kFront = "[[1,0,0,0],[0,1,0,0],[0,0,1,4],[0,0,0,1]]";
const char* kSide = "[[0,0,1,4],[0,1,0,0],[-1,0,0,0],[0,0,0,1]]";

// RGBA 16x12 frame whose alpha is 0 in the left quarter, 0.4 in the next, 1 elsewhere.
io::ImageF rgba_frame(int seed) {
  io::ImageF im = test::pattern(16, 12, 4, seed);
  for (int y = 0; y < 12; ++y) {
    for (int x = 0; x < 16; ++x) im.data[static_cast<size_t>((y * 16 + x) * 4 + 3)] = x < 4 ? 0.0f : x < 8 ? 0.4f : 1.0f;
  }
  return im;
}

void write_dnerf(const std::filesystem::path& root) {
  for (const char* split : {"train", "val", "test"}) std::filesystem::create_directories(root / split);
  for (int i = 0; i < 3; ++i) io::write_png(root / "train" / ("r_00" + std::to_string(i) + ".png"), rgba_frame(i));
  io::write_png(root / "train" / "r_003.png", test::pattern(8, 6, 4, 3));
  io::write_png(root / "val" / "r_000.png", rgba_frame(7));
  io::write_png(root / "test" / "r_000.png", rgba_frame(8));
  // camera_angle_x = 2 atan(8 / 10) gives focal 10 on a 16-wide image.
  test::write_raw(root / "transforms_train.json", std::string(R"({"camera_angle_x": 1.3494818844471055, "frames": [
    {"file_path": "./train/r_000", "time": 0.0, "transform_matrix": )") + kFront + R"(},
    {"file_path": "./train/r_001", "time": 0.5, "transform_matrix": )" + kSide + R"(},
    {"file_path": "./train/r_002.png", "time": 1.0, "transform_matrix": )" + kFront + R"(},
    {"file_path": "./train/r_003", "time": 0.25, "fl_x": 3, "fl_y": 3.5, "cx": 4.25, "cy": 2.75, "w": 8, "h": 6,
     "transform_matrix": )" + kSide + R"(}]})");
  test::write_raw(root / "transforms_val.json", std::string(R"({"camera_angle_x": 1.3494818844471055, "frames": [
    {"file_path": "./val/r_000", "time": 0.75, "transform_matrix": )") + kFront + "}]}");
  test::write_raw(root / "transforms_test.json", std::string(R"({"camera_angle_x": 1.3494818844471055, "frames": [
    {"file_path": "./test/r_000", "time": 0.125, "transform_matrix": )") + kSide + "}]}");
}

}  // namespace

TEST_CASE("dnerf: views, times, split and per-frame intrinsics") {
  test::TempDir dir("dnerf_basic");
  const auto root = dir / "scene";
  write_dnerf(root);
  const data::Dataset d = data::load_dataset(root);
  CHECK(d.kind == "dnerf");
  CHECK(d.background == std::array<float, 3>{1, 1, 1});
  REQUIRE(d.views.size() == 6);
  const std::vector<std::string> names = {"train/r_000", "train/r_001", "train/r_002", "train/r_003", "val/r_000", "test/r_000"};
  const std::vector<double> times = {0, 0.5, 1, 0.25, 0.75, 0.125};
  for (size_t i = 0; i < 6; ++i) {
    CHECK(d.views[i].name == names[i]);
    CHECK(d.views[i].time == times[i]);
    CHECK(d.views[i].test == (i >= 4));
    CHECK(d.views[i].camera_index == -1);
    CHECK(d.views[i].image == root / (names[i] + ".png"));
  }
  const io::CameraView& c = d.views[0].camera;
  CHECK(c.width == 16);
  CHECK(c.height == 12);
  CHECK(c.fx == doctest::Approx(10));
  CHECK(c.cx == 8);
  CHECK(test::project(c, {1, 0, 0})[0] == doctest::Approx(8 + 10.0 / 4));
  // The per-frame intrinsics win over the global angle and the first image's size (copied, so exact).
  const io::CameraView& small = d.views[3].camera;
  CHECK(small.width == 8);
  CHECK(small.height == 6);
  CHECK(small.fx == 3);
  CHECK(small.fy == 3.5);
  CHECK(small.cx == 4.25);
  CHECK(small.cy == 2.75);
  // Train centres: (0,0,4) twice and (4,0,0) twice; mean (2,0,2); distance 2 sqrt 2.
  CHECK(d.extent == doctest::Approx(1.1 * 2 * std::sqrt(2.0)));
}

TEST_CASE("dnerf: RGBA frames are composited on the background") {
  test::TempDir dir("dnerf_rgba");
  const auto root = dir / "scene";
  write_dnerf(root);
  for (const float bg : {1.0f, 0.25f}) {
    const data::Dataset d = data::load_dnerf(root, {.downscale = 1, .background = std::array<float, 3>{bg, bg, bg}});
    data::FrameCache cache(d, 1 << 20);
    const io::ImageF& im = cache.get(d.views[1]);
    REQUIRE(im.channels == 3);
    for (int x : {1, 5, 12}) {
      const float a = x < 4 ? 0.0f : x < 8 ? 0.4f : 1.0f;
      for (int k = 0; k < 3; ++k) {
        const float expected = test::level(x, 2, k, 1) * a + bg * (1 - a);
        CHECK(im.data[static_cast<size_t>((2 * 16 + x) * 3 + k)] == doctest::Approx(expected).epsilon(1e-6));
      }
    }
    CHECK(cache.get(d.views[3]).width == 8);
  }
}

TEST_CASE("dnerf: downscale composites before filtering") {
  test::TempDir dir("dnerf_downscale");
  const auto root = dir / "scene";
  write_dnerf(root);
  const data::Dataset d = data::load_dnerf(root, {.downscale = 2, .background = {}});
  CHECK(d.views[0].camera.width == 8);
  CHECK(d.views[0].camera.fx == doctest::Approx(5));
  CHECK(d.views[3].camera.width == 4);
  CHECK(d.views[3].camera.fy == 1.75);  // per-frame intrinsics are downscaled too (halving is exact)
  CHECK(d.views[3].camera.cy == 1.375);
  data::FrameCache cache(d, 1 << 20);
  const io::ImageF& im = cache.get(d.views[0]);
  REQUIRE(im.width == 8);
  // Output pixel (2, 0) covers x = 4, 5 (alpha 0.4) on white.
  float expected = 0;
  for (int y = 0; y < 2; ++y) {
    for (int x = 4; x < 6; ++x) expected += (test::level(x, y, 0, 0) * 0.4f + 0.6f) / 4;
  }
  CHECK(im.data[2 * 3] == doctest::Approx(expected).epsilon(1e-6));
}
