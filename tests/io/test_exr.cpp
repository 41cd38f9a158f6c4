// OpenEXR: 32-bit float round trip and error messages.
#include <doctest/doctest.h>

#include <cstring>
#include <random>
#include <string>

#include "io_test_util.h"
#include "s4d/io/image_io.h"

using s4d::test::error_at;
using s4d::test::TempDir;

TEST_CASE("EXR round trip of five float channels is bit-exact") {
  TempDir dir("exr_round_trip");
  constexpr int kW = 13, kH = 7;
  std::mt19937 rng(3);
  std::normal_distribution<float> normal(0.0f, 10.0f);
  const std::vector<std::string> names = {"R", "G", "B", "A", "Z"};
  std::vector<std::vector<float>> planes(names.size(), std::vector<float>(kW * kH));
  for (auto& p : planes) {
    for (float& v : p) v = normal(rng);
  }
  planes[4][0] = 1e30f;  // far depth must survive too
  std::vector<std::pair<std::string, const float*>> channels;
  for (size_t c = 0; c < names.size(); ++c) channels.emplace_back(names[c], planes[c].data());

  s4d::io::write_exr(dir / "out.exr", kW, kH, channels);
  const s4d::io::ExrImage img = s4d::io::read_exr(dir / "out.exr");
  CHECK(img.width == kW);
  CHECK(img.height == kH);
  REQUIRE(img.channels.size() == names.size());
  for (size_t c = 0; c < names.size(); ++c) {
    CAPTURE(names[c]);
    REQUIRE(img.channels.count(names[c]) == 1);
    const std::vector<float>& got = img.channels.at(names[c]);
    REQUIRE(got.size() == planes[c].size());
    // Lossless ZIP on FLOAT channels: bits must not change.
    CHECK(std::memcmp(got.data(), planes[c].data(), got.size() * sizeof(float)) == 0);
  }
}

TEST_CASE("EXR reader names the file when it is missing or unreadable") {
  TempDir dir("exr_errors");
  CHECK_THROWS_WITH_AS(s4d::io::read_exr(dir / "missing.exr"), error_at(dir / "missing.exr", "cannot open"),
                       std::runtime_error);
  s4d::test::write_raw(dir / "junk.exr", "definitely not an OpenEXR file");
  CHECK_THROWS_WITH_AS(s4d::io::read_exr(dir / "junk.exr"), error_at(dir / "junk.exr", "cannot read EXR"),
                       std::runtime_error);

  const std::vector<float> plane(16, 1.0f);
  s4d::io::write_exr(dir / "full.exr", 4, 4, {{"Z", plane.data()}});
  const std::string full = s4d::test::read_raw(dir / "full.exr");
  s4d::test::write_raw(dir / "cut.exr", full.substr(0, full.size() - 10));
  CHECK_THROWS_WITH_AS(s4d::io::read_exr(dir / "cut.exr"), error_at(dir / "cut.exr", "cannot read EXR"),
                       std::runtime_error);
}

TEST_CASE("EXR writer rejects bad arguments") {
  TempDir dir("exr_bad_args");
  const std::vector<float> plane(4, 0.0f);
  CHECK_THROWS_AS(s4d::io::write_exr(dir / "x.exr", 0, 2, {{"R", plane.data()}}), std::invalid_argument);
  CHECK_THROWS_AS(s4d::io::write_exr(dir / "x.exr", 2, 2, {}), std::invalid_argument);
  CHECK_THROWS_AS(s4d::io::write_exr(dir / "x.exr", 2, 2, {{"R", plane.data()}, {"R", plane.data()}}),
                  std::invalid_argument);
  CHECK_THROWS_AS(s4d::io::write_exr(dir / "x.exr", 2, 2, {{"R", nullptr}}), std::invalid_argument);
  CHECK_FALSE(std::filesystem::exists(dir / "x.exr"));
}
