// PNG: 8/16-bit round trips, clamping and NaN, palette expansion, error messages.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <random>
#include <string>

#include "max_abs_diff.h"
#include "io_test_util.h"
#include "s4d/io/image_io.h"

using s4d::io::ImageF;
using s4d::test::error_at;
using s4d::test::TempDir;
using s4d::test::max_abs_diff;

namespace {

ImageF random_image(int w, int h, int c, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  ImageF img{w, h, c, {}};
  img.data.resize(static_cast<size_t>(w * h * c));
  for (float& v : img.data) v = u(rng);
  return img;
}

}  // namespace

TEST_CASE("8-bit PNG round trip is within half a level for 1 to 4 channels") {
  TempDir dir("png_8bit");
  for (int c = 1; c <= 4; ++c) {
    CAPTURE(c);
    const ImageF in = random_image(7, 5, c, 100u + static_cast<unsigned>(c));
    const auto path = dir / ("img" + std::to_string(c) + ".png");
    s4d::io::write_png(path, in);
    const ImageF out = s4d::io::read_png(path);
    REQUIRE(out.width == 7);
    REQUIRE(out.height == 5);
    REQUIRE(out.channels == c);
    REQUIRE(out.data.size() == in.data.size());
    // Round-to-nearest quantisation errs by at most half a level; 1e-6 covers the float
    // rounding of v * 255 and level / 255.
    CHECK(max_abs_diff(in, out) <= 0.5f / 255.0f + 1e-6f);
  }
}

TEST_CASE("16-bit PNG round trip is within half a level") {
  TempDir dir("png_16bit");
  const ImageF in = random_image(9, 4, 3, 7);
  s4d::io::write_png(dir / "img.png", in, 16);
  const ImageF out = s4d::io::read_png(dir / "img.png");
  REQUIRE(out.data.size() == in.data.size());
  // Half a level of 65535, plus float rounding of values near 1 (ulp 6e-8).
  CHECK(max_abs_diff(in, out) <= 0.5f / 65535.0f + 1e-7f);
}

TEST_CASE("PNG writer clamps to [0, 1] and writes NaN as 0") {
  TempDir dir("png_clamp");
  const float inf = std::numeric_limits<float>::infinity();
  const ImageF in{6, 1, 1, {-0.5f, 1.5f, std::numeric_limits<float>::quiet_NaN(), 0.25f, inf, -inf}};
  s4d::io::write_png(dir / "clamp.png", in);
  const ImageF out = s4d::io::read_png(dir / "clamp.png");
  REQUIRE(out.data.size() == 6);
  // Levels are integers and the reader computes level / 255 exactly like these expectations.
  CHECK(out.data[0] == 0.0f);
  CHECK(out.data[1] == 1.0f);
  CHECK(out.data[2] == 0.0f);
  CHECK(out.data[3] == 64.0f / 255.0f);  // 0.25 * 255 + 0.5 = 64.25 -> 64
  CHECK(out.data[4] == 1.0f);
  CHECK(out.data[5] == 0.0f);
}

TEST_CASE("a 2-bit palette PNG with transparency reads as RGBA") {
  // Built by hand (Python zlib + struct): 2x2, bit depth 2, palette red, green, blue, tRNS
  // alpha 255, 255, 128; pixel indices [[0, 1], [2, 0]].
  const unsigned char kPalettePng[] = {
      0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x48, 0x44, 0x52, 0x00, 0x00,
      0x00, 0x02, 0x00, 0x00, 0x00, 0x02, 0x02, 0x03, 0x00, 0x00, 0x00, 0x0f, 0xd8, 0xe5, 0xb7, 0x00, 0x00, 0x00,
      0x09, 0x50, 0x4c, 0x54, 0x45, 0xff, 0x00, 0x00, 0x00, 0xff, 0x00, 0x00, 0x00, 0xff, 0x2d, 0x4a, 0xcd, 0x8a,
      0x00, 0x00, 0x00, 0x03, 0x74, 0x52, 0x4e, 0x53, 0xff, 0xff, 0x80, 0x3a, 0x72, 0x8e, 0x61, 0x00, 0x00, 0x00,
      0x0c, 0x49, 0x44, 0x41, 0x54, 0x78, 0xda, 0x63, 0x10, 0x60, 0x68, 0x00, 0x00, 0x00, 0xb4, 0x00, 0x91, 0x3e,
      0xf7, 0x0b, 0x1f, 0x00, 0x00, 0x00, 0x00, 0x49, 0x45, 0x4e, 0x44, 0xae, 0x42, 0x60, 0x82};
  TempDir dir("png_palette");
  s4d::test::write_raw(dir / "palette.png",
                       std::string(reinterpret_cast<const char*>(kPalettePng), sizeof(kPalettePng)));
  const ImageF img = s4d::io::read_png(dir / "palette.png");
  REQUIRE(img.width == 2);
  REQUIRE(img.height == 2);
  REQUIRE(img.channels == 4);
  // Levels 0, 128 and 255 divided by 255, as the reader does: exact.
  const std::vector<float> expected = {1, 0, 0, 1, 0, 1, 0, 1, 0, 0, 1, 128.0f / 255.0f, 1, 0, 0, 1};
  CHECK(img.data == expected);
}

TEST_CASE("PNG reader names the file when it is missing, not a PNG or truncated") {
  TempDir dir("png_errors");
  CHECK_THROWS_WITH_AS(s4d::io::read_png(dir / "missing.png"), error_at(dir / "missing.png", "cannot open"),
                       std::runtime_error);

  s4d::test::write_raw(dir / "text.png", "hello, not a png");
  CHECK_THROWS_WITH_AS(s4d::io::read_png(dir / "text.png"), error_at(dir / "text.png", "not a PNG file"),
                       std::runtime_error);

  s4d::io::write_png(dir / "full.png", random_image(32, 32, 3, 9));
  const std::string full = s4d::test::read_raw(dir / "full.png");
  s4d::test::write_raw(dir / "cut.png", full.substr(0, full.size() / 2));
  CHECK_THROWS_WITH_AS(s4d::io::read_png(dir / "cut.png"), error_at(dir / "cut.png", "corrupt PNG: truncated"),
                       std::runtime_error);

  // Cut just before IEND: the pixels decode, the end of the stream is missing.
  s4d::test::write_raw(dir / "no_end.png", full.substr(0, full.size() - 12));
  CHECK_THROWS_WITH_AS(s4d::io::read_png(dir / "no_end.png"), error_at(dir / "no_end.png", "corrupt PNG"),
                       std::runtime_error);
}

TEST_CASE("PNG writer rejects bad shapes") {
  TempDir dir("png_bad_shape");
  CHECK_THROWS_AS(s4d::io::write_png(dir / "x.png", ImageF{2, 2, 5, std::vector<float>(20)}), std::invalid_argument);
  CHECK_THROWS_AS(s4d::io::write_png(dir / "x.png", ImageF{2, 2, 3, std::vector<float>(11)}), std::invalid_argument);
  CHECK_THROWS_AS(s4d::io::write_png(dir / "x.png", ImageF{2, 2, 3, std::vector<float>(12)}, 12),
                  std::invalid_argument);
  CHECK_FALSE(std::filesystem::exists(dir / "x.png"));
}
