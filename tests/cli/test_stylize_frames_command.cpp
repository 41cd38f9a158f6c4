// `style4d stylize-frames` end to end on 3 tiny frames (a folder of PNGs and an mp4; the patch
// stylizer, and adain with random weights at VGG19's real shapes), and its error cases: a missing
// style file, an empty input folder, an unknown or weightless stylizer, weights for patch, missing
// weight files, a frame too large for adain, a bad strength, the input as output. Each failure is
// one line naming what is wrong, and writes nothing. Also `make-style`.
#include <doctest/doctest.h>

#include <algorithm>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "cli_run.h"
#include "nn_fixture.h"
#include "s4d/io/image_io.h"

namespace fs = std::filesystem;

namespace {

int run(const std::string& command, const std::string& args, const fs::path& log) {
  return s4d::test::run_style4d(command, args, log);
}
std::string read_text(const fs::path& p) { return s4d::test::read_text(p); }

// Three 32x24 frames of a gradient with a bright square moving right by 2 pixels a frame.
fs::path write_frames(const fs::path& dir) {
  const fs::path in = dir / "in";
  fs::create_directories(in);
  for (int t = 0; t < 3; ++t) {
    s4d::io::ImageF f{32, 24, 3, std::vector<float>(32 * 24 * 3)};
    for (int y = 0; y < 24; ++y)
      for (int x = 0; x < 32; ++x) {
        const bool square = x >= 6 + 2 * t && x < 14 + 2 * t && y >= 8 && y < 16;
        float* p = &f.data[(static_cast<size_t>(y) * 32 + x) * 3];
        p[0] = square ? 0.9f : 0.2f + 0.5f * static_cast<float>(x) / 32;
        p[1] = square ? 0.8f : 0.3f;
        p[2] = square ? 0.1f : 0.3f + 0.4f * static_cast<float>(y) / 24;
      }
    s4d::io::write_png(in / ("frame_" + std::to_string(t) + ".png"), f);
  }
  return in;
}

bool one_error_line(const fs::path& log, const std::string& needle) {
  const std::string text = read_text(log);
  return text.find("error") != std::string::npos && text.find(needle) != std::string::npos &&
         std::count(text.begin(), text.end(), '\n') == 1;
}

}  // namespace

TEST_CASE("stylize-frames restyles a folder of frames with the built-in style") {
  const fs::path dir = s4d::test::fresh_dir("stylize_ok");
  const fs::path in = write_frames(dir);
  REQUIRE(run("make-style", "--out " + (dir / "style.png").string() + " --size 64", dir / "style_log.txt") == 0);
  REQUIRE(run("stylize-frames", "--in " + in.string() + " --style-image " + (dir / "style.png").string() + " --out " +
                                    (dir / "out").string() + " --seed 2",
              dir / "log.txt") == 0);
  for (int t = 0; t < 3; ++t) {
    const s4d::io::ImageF f = s4d::io::read_png(dir / "out" / ("frame_" + std::to_string(t) + ".png"));
    CHECK(f.width == 32);
    CHECK(f.height == 24);
    CHECK(f.channels == 3);
  }
  CHECK(read_text(dir / "log.txt").find("stylized 3 frames (32x24) with patch") != std::string::npos);

  // --strength 0 writes the content back (8-bit round trip: exactly).
  REQUIRE(run("stylize-frames", "--in " + in.string() + " --style-image " + (dir / "style.png").string() + " --out " +
                                    (dir / "same").string() + " --strength 0",
              dir / "log.txt") == 0);
  CHECK(s4d::io::read_png(dir / "same" / "frame_1.png").data == s4d::io::read_png(in / "frame_1.png").data);
}

TEST_CASE("stylize-frames reads and writes videos") {
  const fs::path dir = s4d::test::fresh_dir("stylize_video");
  const fs::path in = write_frames(dir);
  REQUIRE(run("make-style", "--out " + (dir / "style.png").string() + " --size 64", dir / "log.txt") == 0);
  REQUIRE(run("stylize-frames", "--in " + in.string() + " --style-image " + (dir / "style.png").string() + " --out " +
                                    (dir / "out.mp4").string(),
              dir / "log.txt") == 0);
  REQUIRE(fs::file_size(dir / "out.mp4") > 0);
  REQUIRE(run("stylize-frames", "--in " + (dir / "out.mp4").string() + " --style-image " + (dir / "style.png").string() +
                                    " --out " + (dir / "back").string(),
              dir / "log.txt") == 0);
  CHECK(fs::exists(dir / "back" / "0000.png"));
  CHECK(fs::exists(dir / "back" / "0002.png"));
}

TEST_CASE("stylize-frames refuses bad inputs with one line and writes nothing") {
  const fs::path dir = s4d::test::fresh_dir("stylize_bad");
  const fs::path in = write_frames(dir);
  REQUIRE(run("make-style", "--out " + (dir / "style.png").string() + " --size 64", dir / "log.txt") == 0);
  const std::string style = " --style-image " + (dir / "style.png").string();
  const std::string out = " --out " + (dir / "out").string();

  CHECK(run("stylize-frames", "--in " + in.string() + " --style-image " + (dir / "missing.png").string() + out, dir / "log.txt") != 0);
  CHECK(one_error_line(dir / "log.txt", "missing.png"));

  fs::create_directories(dir / "empty");
  CHECK(run("stylize-frames", "--in " + (dir / "empty").string() + style + out, dir / "log.txt") != 0);
  CHECK(one_error_line(dir / "log.txt", "no PNG frames"));

  CHECK(run("stylize-frames", "--in " + in.string() + style + out + " --stylizer nope", dir / "log.txt") != 0);
  CHECK(one_error_line(dir / "log.txt", "available: patch"));

  CHECK(run("stylize-frames", "--in " + in.string() + style + out + " --stylizer adain", dir / "log.txt") != 0);
  CHECK(one_error_line(dir / "log.txt", "adain needs weights: --weights DIR holding vgg_normalised.safetensors"));

  CHECK(run("stylize-frames", "--in " + in.string() + style + out + " --weights " + dir.string(), dir / "log.txt") !=
        0);
  CHECK(one_error_line(dir / "log.txt", "patch needs no weights"));

  for (const std::string strength : {"1.5", "-0.1", "x", "0.5x"}) {
    CAPTURE(strength);
    CHECK(run("stylize-frames", "--in " + in.string() + style + out + " --strength " + strength, dir / "log.txt") != 0);
    CHECK(one_error_line(dir / "log.txt", "--strength"));
  }
  CHECK_FALSE(fs::exists(dir / "out"));

  CHECK(run("stylize-frames", "--in " + in.string() + style + " --out " + in.string(), dir / "log.txt") != 0);
  CHECK(one_error_line(dir / "log.txt", "is the input"));
}

TEST_CASE("stylize-frames runs adain from a folder of safetensors weights and names what is missing") {
  const fs::path dir = s4d::test::fresh_dir("stylize_adain");
  const fs::path in = write_frames(dir);
  REQUIRE(run("make-style", "--out " + (dir / "style.png").string() + " --size 64", dir / "log.txt") == 0);
  // Random weights at the published networks' shapes, as the README's conversion line writes them.
  std::mt19937 rng(31);
  const fs::path weights = dir / "weights";
  fs::create_directories(weights);
  s4d::test::write_params(weights / "vgg_normalised.safetensors", s4d::test::random_vgg({}, 4, rng));
  const std::string common = " --style-image " + (dir / "style.png").string() + " --stylizer adain --style-size 32";

  CHECK(run("stylize-frames", "--in " + in.string() + common + " --weights " + weights.string() + " --out " +
                                  (dir / "out").string(),
            dir / "log.txt") != 0);
  CHECK(one_error_line(dir / "log.txt", (weights / "decoder.safetensors").string() + ": cannot open"));

  s4d::test::write_params(weights / "decoder.safetensors", s4d::test::random_decoder({}, rng));
  REQUIRE(run("stylize-frames", "--in " + in.string() + common + " --weights " + weights.string() + " --out " +
                                    (dir / "out").string(),
              dir / "log.txt") == 0);
  for (int t = 0; t < 3; ++t) {
    const s4d::io::ImageF f = s4d::io::read_png(dir / "out" / ("frame_" + std::to_string(t) + ".png"));
    CHECK(f.width == 32);
    CHECK(f.height == 24);
  }
  CHECK(read_text(dir / "log.txt").find("stylized 3 frames (32x24) with adain") != std::string::npos);

  // hgst reads MCCNet's module too.
  CHECK(run("stylize-frames", "--in " + in.string() + " --style-image " + (dir / "style.png").string() +
                                  " --stylizer hgst --weights " + weights.string() + " --out " + (dir / "hgst").string(),
            dir / "log.txt") != 0);
  CHECK(one_error_line(dir / "log.txt", (weights / "mcc_module.safetensors").string() + ": cannot open"));

  // A frame whose 64-channel feature maps (130 MiB) pass lavapipe's 128 MiB storage-buffer limit.
  const fs::path large = dir / "large";
  fs::create_directories(large);
  s4d::io::write_png(large / "0.png", s4d::io::ImageF{1024, 520, 3, std::vector<float>(1024 * 520 * 3, 0.5f)});
  CHECK(run("stylize-frames", "--in " + large.string() + common + " --weights " + weights.string() + " --out " +
                                  (dir / "large_out").string(),
            dir / "log.txt") != 0);
  CHECK(one_error_line(dir / "log.txt", "adain: a 1024x520 frame needs 130 MiB feature maps"));
  CHECK_FALSE(fs::exists(dir / "large_out"));
}
