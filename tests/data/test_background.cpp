// The background found from the frames (background.cpp): alpha means the layout's convention, opaque
// frames with one uniform border colour were rendered on it (public D-NeRF copies with alpha dropped),
// real captures keep the default; an explicit background the borders contradict is reported.
#include <doctest/doctest.h>

#include "data_test_util.h"

using namespace s4d;

namespace {

const char* kFront = "[[1,0,0,0],[0,1,0,0],[0,0,1,4],[0,0,0,1]]";

// A 24x16 frame: an object (the fine test pattern) in the middle on `border`, or with alpha 0 there.
io::ImageF frame(int seed, const std::array<float, 3>& border, bool alpha) {
  const int w = 24, h = 16, c = alpha ? 4 : 3;
  io::ImageF im = test::pattern(w, h, c, seed);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const bool object = x >= 6 && x < 18 && y >= 4 && y < 12;
      float* p = &im.data[static_cast<size_t>((y * w + x) * c)];
      if (alpha) p[3] = object ? 1.0f : 0.0f;
      else if (!object) p[0] = border[0], p[1] = border[1], p[2] = border[2];
    }
  }
  return im;
}

void write_scene(const std::filesystem::path& root, const std::array<float, 3>& border, bool alpha) {
  for (const char* split : {"train", "test"}) {
    std::filesystem::create_directories(root / split);
    std::string frames;
    for (int i = 0; i < 3; ++i) {
      io::write_png(root / split / ("r_00" + std::to_string(i) + ".png"), frame(i, border, alpha));
      frames += std::string(i ? "," : "") + R"({"file_path": "./)" + split + "/r_00" + std::to_string(i) +
                R"(", "time": )" + std::to_string(i / 2.0) + R"(, "transform_matrix": )" + kFront + "}";
    }
    test::write_raw(root / ("transforms_" + std::string(split) + ".json"),
                    R"({"camera_angle_x": 1.0, "frames": [)" + frames + "]}");
  }
}

}  // namespace

TEST_CASE("background: black borders without alpha are found, whatever the layout's default") {
  test::TempDir dir("background_black");
  write_scene(dir / "s", {0, 0, 0}, false);
  const data::Dataset d = data::load_dataset(dir / "s");
  CHECK(d.background_source == "borders");
  CHECK(d.background == std::array<float, 3>{0, 0, 0});  // D-NeRF's default would be white
  CHECK(d.background_conflict.empty());
}

TEST_CASE("background: a coloured uniform border is taken as it is") {
  test::TempDir dir("background_colour");
  write_scene(dir / "s", {0.2f, 0.6f, 1.0f}, false);
  const data::Dataset d = data::load_dataset(dir / "s");
  CHECK(d.background_source == "borders");
  for (size_t k = 0; k < 3; ++k) CHECK(d.background[k] == doctest::Approx(std::array{0.2, 0.6, 1.0}[k]).epsilon(0.01));
}

TEST_CASE("background: frames with alpha keep the layout's convention (white for D-NeRF)") {
  test::TempDir dir("background_alpha");
  write_scene(dir / "s", {0, 0, 0}, true);
  const data::Dataset d = data::load_dataset(dir / "s");
  CHECK(d.background_source == "alpha");
  CHECK(d.background == std::array<float, 3>{1, 1, 1});
}

TEST_CASE("background: a real capture (no uniform border) keeps the default; the probe can be skipped") {
  test::TempDir dir("background_real");
  write_scene(dir / "s", {0, 0, 0}, false);
  for (int i = 0; i < 3; ++i) {  // the fine pattern everywhere: no border colour to find
    io::write_png(dir / "s" / "train" / ("r_00" + std::to_string(i) + ".png"), test::pattern(24, 16, 3, i));
  }
  CHECK(data::load_dataset(dir / "s").background_source == "layout (opaque frames)");
  CHECK(data::load_dataset(dir / "s", {.probe_background = false}).background_source == "layout");
}

TEST_CASE("background: an explicit colour the borders contradict is kept and reported") {
  test::TempDir dir("background_conflict");
  write_scene(dir / "s", {0, 0, 0}, false);
  const data::Dataset d = data::load_dataset(dir / "s", {.background = std::array<float, 3>{1, 1, 1}});
  CHECK(d.background_source == "option");
  CHECK(d.background == std::array<float, 3>{1, 1, 1});
  CHECK(d.background_conflict ==
        "the frames are opaque with a uniform 0.00,0.00,0.00 border, but the background asked for is 1.00,1.00,1.00");
  // A close one is no conflict.
  CHECK(data::load_dataset(dir / "s", {.background = std::array<float, 3>{0.1f, 0.1f, 0.1f}}).background_conflict.empty());
}
