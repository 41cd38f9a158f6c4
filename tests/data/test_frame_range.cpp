// --frames: a cap on the frames of a capture, by index of distinct time, their times mapped back onto [0, 1].
#include <doctest/doctest.h>

#include "s4d/data/dataset.h"
#include "s4d/synth/dataset.h"
#include "../io/io_test_util.h"

using namespace s4d;

TEST_CASE("frame range: parsing") {
  CHECK(data::parse_frame_range("5") == std::pair{0, 5});
  CHECK(data::parse_frame_range("2:7") == std::pair{2, 7});
  for (const char* bad : {"", "0", "3:3", "4:2", "-1:3", "a", "1:", ":4", "1:2:3", "1e3", "99999999999"}) {
    CHECK_THROWS_AS(data::parse_frame_range(bad), std::invalid_argument);
  }
  CHECK_THROWS_WITH(data::parse_frame_range("x", "--frames"), "--frames: expected N or A:B (frame indices), got 'x'");
}

TEST_CASE("frame range: DyNeRF keeps every camera's frames A..B-1 with times on [0, 1]") {
  test::TempDir dir("frame_range");
  synth::write_dataset(dir / "s", {.cams = 3, .frames = 6, .width = 16, .height = 12, .points = 50});
  const data::Dataset all = data::load_dataset(dir / "s");
  const data::Dataset some = data::load_dataset(dir / "s", {.frames = std::pair{2, 5}});
  REQUIRE(some.views.size() == 3 * 3);
  for (const data::View& v : some.views) {
    const std::string frame = v.name.substr(v.name.find('/') + 1);
    CHECK((frame == "0002" || frame == "0003" || frame == "0004"));
    // (0.6 - 0.4) / (0.8 - 0.4) is 0.5 only to rounding: 5.6e-17 off measured.
    CHECK(v.time == doctest::Approx(frame == "0002" ? 0.0 : frame == "0003" ? 0.5 : 1.0).epsilon(1e-12));
    CHECK(v.camera.time == v.time);
  }
  CHECK(some.extent == all.extent);  // the cameras are the same
  CHECK(data::load_dataset(dir / "s", {.frames = std::pair{0, 1}}).views.size() == 3);
  CHECK_THROWS_WITH_AS(data::load_dataset(dir / "s", {.frames = std::pair{0, 7}}),
                       ((dir / "s").string() + ": --frames 0:7: the dataset has 6 frames (distinct times)").c_str(),
                       std::runtime_error);
}
