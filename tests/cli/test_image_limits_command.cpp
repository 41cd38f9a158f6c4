// Images too large for the memory at hand are refused before decoding, saying how much they need
// (a style image in stylize-frames, make-style --size), and a damaged PNG gives one error line with
// no line of libpng's own.
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "cli_run.h"

namespace fs = std::filesystem;
using s4d::test::exit_code;
using s4d::test::read_text;

namespace {

uint32_t crc32(const std::string& bytes) {
  uint32_t c = 0xffffffffu;
  for (unsigned char b : bytes) {
    c ^= b;
    for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xedb88320u & (0u - (c & 1u)));
  }
  return ~c;
}

std::string be32(uint32_t v) {
  return {static_cast<char>(v >> 24), static_cast<char>(v >> 16), static_cast<char>(v >> 8), static_cast<char>(v)};
}

std::string chunk(const std::string& type, const std::string& data) {
  return be32(static_cast<uint32_t>(data.size())) + type + data + be32(crc32(type + data));
}

// A PNG whose header says width x height RGB at 8 bits, with an empty image stream: what it needs is
// known from the header alone (the bytes a decoder would be asked to fill are never there).
void write_png_header(const fs::path& file, uint32_t width, uint32_t height) {
  const std::string ihdr = be32(width) + be32(height) + std::string("\x08\x02\x00\x00\x00", 5);
  std::ofstream(file, std::ios::binary) << std::string("\x89PNG\r\n\x1a\n", 8) + chunk("IHDR", ihdr) +
                                               chunk("IDAT", std::string("\x78\x9c\x03\x00\x00\x00\x00\x01", 8)) +
                                               chunk("IEND", "");
}

int style4d_limited(const std::string& args, const fs::path& log) {
  // 2 GB of address space: the program starts, a 16,000 x 16,000 picture (about 7 GB decoded) cannot.
  const std::string cmd = "ulimit -v 2000000 && " + std::string(S4D_STYLE4D_EXE) + " " + args + " > " + log.string() + " 2>&1";
  return exit_code(std::system(("bash -c '" + cmd + "'").c_str()));
}

}  // namespace

TEST_CASE("a style image too large for the memory at hand is refused before decoding, saying what it needs") {
  const fs::path dir = s4d::test::fresh_dir("image_limits");
  write_png_header(dir / "huge.png", 16000, 16000);
  fs::create_directories(dir / "frames");
  write_png_header(dir / "frames" / "0000.png", 32, 24);
  const fs::path log = dir / "log.txt";
  CHECK(style4d_limited("stylize-frames --in " + (dir / "frames").string() + " --style-image " + (dir / "huge.png").string() +
                            " --out " + (dir / "out").string(),
                        log) == 1);
  const std::string text = read_text(log);
  CHECK_MESSAGE(text.find("style4d stylize-frames: error: " + (dir / "huge.png").string() +
                          ": decoding its 16000x16000 pixels needs about 6912.0 MB of memory, ") != std::string::npos,
                text);
  CHECK_MESSAGE(text.find(" MB is available\n") != std::string::npos, text);
  CHECK(std::count(text.begin(), text.end(), '\n') == 1);
  CHECK_FALSE(fs::exists(dir / "out"));
}

TEST_CASE("make-style --size too large for the memory is refused before painting") {
  const fs::path dir = s4d::test::fresh_dir("make_style_limits");
  const fs::path log = dir / "log.txt";
  CHECK(exit_code(s4d::test::run_style4d("make-style", "--out " + (dir / "s.png").string() + " --size 1000000", log)) == 1);
  const std::string text = read_text(log);
  CHECK_MESSAGE(text.find("style4d make-style: error: --size 1000000: painting 1000000x1000000 pixels needs about "
                          "30000000.0 MB of memory, ") != std::string::npos,
                text);
  CHECK(std::count(text.begin(), text.end(), '\n') == 1);
  CHECK_FALSE(fs::exists(dir / "s.png"));
}

TEST_CASE("a damaged PNG style image is one error line, without libpng's own") {
  const fs::path dir = s4d::test::fresh_dir("damaged_png");
  fs::create_directories(dir / "frames");
  write_png_header(dir / "frames" / "0000.png", 32, 24);
  // A real header cut inside its image data.
  write_png_header(dir / "cut.png", 64, 64);
  fs::resize_file(dir / "cut.png", fs::file_size(dir / "cut.png") - 16);
  const fs::path log = dir / "log.txt";
  CHECK(exit_code(s4d::test::run_style4d("stylize-frames", "--in " + (dir / "frames").string() + " --style-image " +
                                                               (dir / "cut.png").string() + " --out " + (dir / "out").string(),
                                         log)) == 1);
  const std::string text = read_text(log);
  CHECK_MESSAGE(text.find("style4d stylize-frames: error: " + (dir / "cut.png").string() + ": corrupt PNG: ") !=
                    std::string::npos,
                text);
  CHECK(text.find("libpng") == std::string::npos);
  CHECK(std::count(text.begin(), text.end(), '\n') == 1);
}
