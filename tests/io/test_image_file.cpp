// Reading style and content pictures (s4d/io/image_file.h): PNG, JPEG and BMP found by their first
// bytes, as RGB levels / 255; errors name the file.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdio>  // before jpeglib.h, which uses FILE
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <jpeglib.h>

#include "io_test_util.h"
#include "s4d/io/image_file.h"
#include "s4d/io/image_io.h"

using namespace s4d;

namespace {

// A JPEG written by libjpeg itself (not the code under test), quality 100.
void write_jpeg(const std::filesystem::path& path, int width, int height, int components,
                const std::vector<unsigned char>& levels) {
  std::FILE* file = std::fopen(path.c_str(), "wb");
  REQUIRE(file);
  jpeg_compress_struct info{};
  jpeg_error_mgr err{};
  info.err = jpeg_std_error(&err);
  jpeg_create_compress(&info);
  jpeg_stdio_dest(&info, file);
  info.image_width = static_cast<JDIMENSION>(width);
  info.image_height = static_cast<JDIMENSION>(height);
  info.input_components = components;
  info.in_color_space = components == 1 ? JCS_GRAYSCALE : JCS_RGB;
  jpeg_set_defaults(&info);
  jpeg_set_quality(&info, 100, TRUE);
  jpeg_start_compress(&info, TRUE);
  for (int y = 0; y < height; ++y) {
    JSAMPROW row = const_cast<unsigned char*>(levels.data()) + static_cast<size_t>(y * width * components);
    jpeg_write_scanlines(&info, &row, 1);
  }
  jpeg_finish_compress(&info);
  jpeg_destroy_compress(&info);
  std::fclose(file);
}

}  // namespace

TEST_CASE("reading an image names the file on failure") {
  const test::TempDir dir("read_image");
  CHECK_THROWS_WITH_AS(io::read_image_rgb(dir / "missing.png"), doctest::Contains("missing.png"), std::runtime_error);
  std::ofstream(dir / "junk.jpg") << "not an image";
  CHECK_THROWS_WITH_AS(io::read_image_rgb(dir / "junk.jpg"), doctest::Contains("junk.jpg: not a readable image (PNG, JPEG or BMP)"),
                       std::runtime_error);
  std::ofstream(dir / "cut.jpg", std::ios::binary) << "\xff\xd8\xff\xe0";  // a JPEG's first bytes, then nothing
  CHECK_THROWS_WITH_AS(io::read_image_rgb(dir / "cut.jpg"), doctest::Contains("cut.jpg: corrupt JPEG"), std::runtime_error);
}

TEST_CASE("a JPEG reads as RGB, colour and grey alike") {
  const test::TempDir dir("read_jpeg");
  // Flat colour: the DCT is exact on it, so only YCbCr rounding moves the levels.
  const int w = 16, h = 8;
  std::vector<unsigned char> rgb;
  for (int i = 0; i < w * h; ++i) rgb.insert(rgb.end(), {200, 40, 90});
  write_jpeg(dir / "flat.jpg", w, h, 3, rgb);
  const io::ImageF colour = io::read_image_rgb(dir / "flat.jpg");
  REQUIRE(colour.width == w);
  REQUIRE(colour.height == h);
  REQUIRE(colour.channels == 3);
  for (size_t i = 0; i < colour.data.size(); ++i) CHECK(std::abs(colour.data[i] * 255.0f - rgb[i % 3]) <= 2.0f);
  write_jpeg(dir / "grey.jpg", w, h, 1, std::vector<unsigned char>(w * h, 77));
  const io::ImageF grey = io::read_image_rgb(dir / "grey.jpg");
  REQUIRE(grey.channels == 3);
  for (float v : grey.data) CHECK(v == 77.0f / 255.0f);  // grey JPEG is lossless on a flat field
}

TEST_CASE("a PNG with alpha or grey reads as its RGB levels exactly") {
  const test::TempDir dir("read_png_rgb");
  io::ImageF rgba{2, 1, 4, {1.0f, 0.0f, 0.2f, 0.5f, 0.4f, 0.6f, 0.8f, 1.0f}};
  io::write_png(dir / "a.png", rgba);
  const io::ImageF rgb = io::read_image_rgb(dir / "a.png");
  REQUIRE(rgb.channels == 3);
  CHECK(rgb.data == std::vector<float>{1.0f, 0.0f, 51 / 255.0f, 102 / 255.0f, 153 / 255.0f, 204 / 255.0f});
  io::write_png(dir / "g.png", io::ImageF{1, 1, 1, {0.2f}});
  CHECK(io::read_image_rgb(dir / "g.png").data == std::vector<float>(3, 51 / 255.0f));
}

TEST_CASE("an uncompressed BMP reads bottom-up rows as RGB; other BMPs are refused") {
  const test::TempDir dir("read_bmp");
  // 2x2, 24-bit, bottom-up: rows padded to 8 bytes, pixels stored BGR.
  auto header = [](int bits, int compression) {
    std::string h(54, '\0');
    auto put = [&](size_t at, uint32_t v) { for (int i = 0; i < 4; ++i) h[at + i] = static_cast<char>(v >> (8 * i)); };
    h[0] = 'B';
    h[1] = 'M';
    put(10, 54);
    put(14, 40);
    put(18, 2);
    put(22, 2);
    h[26] = 1;
    h[28] = static_cast<char>(bits);
    put(30, static_cast<uint32_t>(compression));
    return h;
  };
  const std::string bottom_row("\x03\x02\x01\x06\x05\x04\0\0", 8), top_row("\x09\x08\x07\x0c\x0b\x0a\0\0", 8);
  std::ofstream(dir / "a.bmp", std::ios::binary) << header(24, 0) << bottom_row << top_row;
  const io::ImageF image = io::read_image_rgb(dir / "a.bmp");
  REQUIRE(image.width == 2);
  REQUIRE(image.height == 2);
  std::vector<float> expected;
  for (int v = 7; v <= 12; ++v) expected.push_back(static_cast<float>(v) / 255.0f);  // top row first
  for (int v = 1; v <= 6; ++v) expected.push_back(static_cast<float>(v) / 255.0f);
  CHECK(image.data == expected);
  std::ofstream(dir / "rle.bmp", std::ios::binary) << header(8, 1) << bottom_row << top_row;
  CHECK_THROWS_WITH_AS(io::read_image_rgb(dir / "rle.bmp"), doctest::Contains("rle.bmp: BMP with 8 bits per pixel, compression 1"),
                       std::runtime_error);
  std::ofstream(dir / "short.bmp", std::ios::binary) << header(24, 0) << bottom_row;
  CHECK_THROWS_WITH_AS(io::read_image_rgb(dir / "short.bmp"), doctest::Contains("short.bmp: BMP is truncated"), std::runtime_error);
}
