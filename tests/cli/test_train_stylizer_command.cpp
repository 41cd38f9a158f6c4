// style4d train-stylizer: a short run on procedural images writes a weights folder with the three
// files the hgst stylizer reads and logs the losses, continues it, or restarts it with --restart;
// wrong settings are refused with the option named.
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <random>
#include <string>

#include "cli_run.h"
#include "nn_fixture.h"
#include "s4d/io/image_io.h"

namespace {

using namespace s4d;

// A 48x40 image of smooth random colours.
io::ImageF smooth_image(std::mt19937& rng) {
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  const float a = u(rng), b = u(rng), c = u(rng);
  io::ImageF img{48, 40, 3, std::vector<float>(size_t{48} * 40 * 3)};
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x)
      for (int ch = 0; ch < 3; ++ch)
        img.data[(size_t(y) * img.width + x) * 3 + ch] = 0.5f + 0.4f * std::sin(a * float(x) + b * float(y) + c * float(ch + 1));
  return img;
}

}  // namespace

TEST_CASE("train-stylizer writes a weights folder and refuses wrong settings") {
  test::ScratchDir dir("cli_train_stylizer");
  std::mt19937 rng(41);
  test::write_params(dir / "vgg.safetensors", test::random_vgg(nn::VggWidths{{4, 6, 8, 12, 10}}, 5, rng));
  std::filesystem::create_directories(dir / "content");
  std::filesystem::create_directories(dir / "styles");
  io::write_png(dir / "content" / "a.png", smooth_image(rng));
  io::write_png(dir / "styles" / "b.png", smooth_image(rng));
  const std::string common = "--content " + (dir / "content").string() + " --styles " + (dir / "styles").string() +
                             " --vgg " + (dir / "vgg.safetensors").string();
  const auto log = dir / "log.txt";
  REQUIRE(test::run_style4d("train-stylizer", common + " --out " + (dir / "w").string() + " --steps 3 --batch 2 --save-every 2 --resize 48 --crop 40", log) == 0);
  const std::string text = test::read_text(log);
  CHECK(text.find("step 3 loss") != std::string::npos);
  CHECK(text.find(" ccpl ") != std::string::npos);  // every term logged, LCL included
  CHECK(text.find("trained 3 steps") != std::string::npos);
  for (const char* f : {"decoder.safetensors", "mcc_module.safetensors", "vgg_normalised.safetensors"})
    CHECK(std::filesystem::exists(dir / "w" / f));
  const std::string again = common + " --out " + (dir / "w").string() + " --batch 2 --save-every 2 --resize 48 --crop 40";
  REQUIRE(test::run_style4d("train-stylizer", again + " --steps 4", log) == 0);
  CHECK(test::read_text(log).find("trained 1 steps") != std::string::npos);
  CHECK(test::run_style4d("train-stylizer", again + " --steps 5 --losses mccnet", log) != 0);
  CHECK(test::read_text(log).find("was trained with --losses full; pass --restart") != std::string::npos);
  REQUIRE(test::run_style4d("train-stylizer", again + " --steps 1 --losses mccnet --restart", log) == 0);
  CHECK(test::read_text(log).find("trained 1 steps") != std::string::npos);
  REQUIRE(test::run_style4d("train-stylizer", again + " --steps 1 --losses ccpl --restart", log) == 0);
  CHECK(test::read_text(log).find("trained 1 steps") != std::string::npos);
  CHECK(test::run_style4d("train-stylizer", again + " --steps 2 --losses lcl", log) != 0);
  CHECK(test::read_text(log).find("was trained with --losses ccpl; pass --restart") != std::string::npos);
  CHECK(test::run_style4d("train-stylizer", common + " --out " + (dir / "x").string() + " --losses cbam", log) != 0);
  CHECK(test::read_text(log).find("--losses: expected one of mccnet, ccpl, content, lcl, full, got 'cbam'") != std::string::npos);

  CHECK(test::run_style4d("train-stylizer", common + " --out " + (dir / "x").string() + " --crop 36", log) != 0);
  CHECK(test::read_text(log).find("--crop: expected a multiple of 8") != std::string::npos);
  CHECK(test::run_style4d("train-stylizer", common + " --out " + (dir / "x").string() + " --save-every 0", log) != 0);
  CHECK(test::read_text(log).find("--save-every: expected 1 or more") != std::string::npos);
  CHECK(test::run_style4d("train-stylizer", common + " --out " + (dir / "x").string() + " --lr fast", log) != 0);
  CHECK(test::read_text(log).find("--lr: expected a number, got 'fast'") != std::string::npos);
  CHECK(test::run_style4d("train-stylizer", "--content " + (dir / "styles" / "b.png").string() + " --styles " +
                                                (dir / "styles").string() + " --vgg " + (dir / "vgg.safetensors").string() +
                                                " --out " + (dir / "x").string(),
                          log) != 0);
  CHECK(test::read_text(log).find("is not a folder") != std::string::npos);
}
