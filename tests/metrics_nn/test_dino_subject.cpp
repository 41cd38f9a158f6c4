// DINO subject consistency's host parts (bench/metrics/dino_subject.cpp) without torch: VBench's
// dino_transform sizes and values, the pair score's clamps, DinoVit's position embedding and the
// errors for weight files that are not a DINO ViT. The network against PyTorch: dino_reference.py.
#include <doctest/doctest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "s4d/io/safetensors.h"
#include "s4d/metrics/dino_subject.h"
#include "s4d/metrics/rgb_tensor.h"
#include "nn_fixture.h"
#include "test_context.h"

namespace {

using namespace s4d;

io::ImageF levels_image(int w, int h) {
  io::ImageF im{w, h, 3, std::vector<float>(size_t(w) * h * 3)};
  for (size_t i = 0; i < im.data.size(); ++i) im.data[i] = float((i * 37) % 256) / 255.0f;
  return im;
}

}  // namespace

TEST_CASE("dino_transform: shorter side 224, longer int(224 long / short), uint8 levels, ImageNet mean/std") {
  const auto landscape = metrics::dino_transform(levels_image(1352, 1014));
  CHECK((landscape.c == 3 && landscape.h == 224 && landscape.w == 298));  // int(224 * 1352 / 1014) = 298
  const auto portrait = metrics::dino_transform(levels_image(31, 37));
  CHECK((portrait.h == 267 && portrait.w == 224));  // int(224 * 37 / 31) = 267
  // A 224-pixel shorter side is kept as is: the input's own levels, normalised.
  const io::ImageF same = levels_image(224, 230);
  const auto kept = metrics::dino_transform(same);
  REQUIRE((kept.h == 230 && kept.w == 224));
  double worst = 0;
  for (uint32_t c = 0; c < 3; ++c)
    for (uint32_t y = 0; y < kept.h; ++y)
      for (uint32_t x = 0; x < kept.w; ++x) {
        const double v = (same.data[(size_t(y) * 224 + x) * 3 + c] - metrics::kImagenetMean[c]) / metrics::kImagenetStd[c];
        worst = std::max(worst, std::abs(kept.at(c, y, x) - v));
      }
  CHECK(worst < 1e-6);  // the same float expression: measured 0
  // Halving 896x448: the mean of 2x2 pixels, here columns of 10 and 13, rounded half to even (11.5 -> 12).
  io::ImageF pair{896, 448, 3, std::vector<float>(896 * 448 * 3, 10.0f / 255.0f)};
  for (size_t p = 1; p < 896 * 448; p += 2) pair.data[p * 3] = 13.0f / 255.0f;
  const auto halved = metrics::dino_transform(pair);
  REQUIRE((halved.h == 224 && halved.w == 448));
  CHECK(std::abs(halved.at(0, 5, 7) * metrics::kImagenetStd[0] + metrics::kImagenetMean[0] - 12.0f / 255.0f) < 1e-6);
  CHECK_THROWS_AS(metrics::dino_transform(io::ImageF{4, 4, 1, std::vector<float>(16, 0.5f)}), std::invalid_argument);
}

TEST_CASE("subject_pair_score averages the cosines to the previous and first frames, each clamped at 0") {
  const std::vector<double> a = {1, 0}, b = {0.6, 0.8}, c = {-1, 0};
  CHECK(metrics::subject_pair_score(a, a, a) == doctest::Approx(1.0));
  CHECK(metrics::subject_pair_score(a, b, b) == doctest::Approx((1.0 + 0.6) / 2));
  CHECK(metrics::subject_pair_score(a, b, c) == doctest::Approx(0.0));  // cosines -1 and -0.6 clamp to 0
  CHECK_THROWS_AS(metrics::subject_pair_score(a, b, {1, 0, 0}), std::invalid_argument);
}

TEST_CASE("dino_position_embedding keeps the grid for square images and resizes it bicubically otherwise") {
  nn::VitShape shape;
  shape.width = 2;
  shape.patch = 16;
  shape.grid = 3;
  // pos [1 + 9, 2]: channel 0 a ramp along x (bicubic keeps linear functions inside the grid), channel 1 constant.
  std::vector<float> pos = {0.5f, -1.0f};
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 3; ++x) pos.insert(pos.end(), {float(x), 2.0f});
  const std::vector<float> cls = {0.25f, 0.75f};
  const auto square = nn::dino_position_embedding(pos, cls, shape, 48, 48);
  REQUIRE(square.size() == 2 * 10);
  CHECK(square[0] == doctest::Approx(0.75));  // class token + its position
  CHECK(square[10] == doctest::Approx(-0.25));
  for (int t = 1; t < 10; ++t) CHECK(square[t] == doctest::Approx(double((t - 1) % 3)));
  // 48x100 pixels: a 3x6 grid, scale factors 3.1 / 3 and 6.1 / 3; the constant channel stays constant
  // (the cubic weights sum to 1) and the ramp increases along x.
  const auto wide = nn::dino_position_embedding(pos, cls, shape, 48, 100);
  REQUIRE(wide.size() == 2 * 19);
  for (int t = 1; t < 19; ++t) CHECK(wide[19 + t] == doctest::Approx(2.0));
  for (int x = 1; x < 6; ++x) CHECK(wide[1 + x] > wide[x]);
  CHECK_THROWS_AS(nn::dino_position_embedding(pos, cls, shape, 8, 48), std::invalid_argument);
}

TEST_CASE("a weight file that is not a DINO ViT is refused naming the file and the tensor") {
  test::ScratchDir dir("dino_subject");
  const auto path = dir / "dino_vitb16.safetensors";
  io::write_safetensors(path, {{"cls_token", {1, 1, 64}, std::vector<float>(64, 0.1f)},
                               {"pos_embed", {1, 5, 64}, std::vector<float>(5 * 64, 0.1f)}});
  try {
    metrics::DinoSubject dino(test::context(), io::SafetensorsFile(path));
    FAIL("a file without patch_embed loaded");
  } catch (const std::exception& e) {
    CHECK(std::string(e.what()).find("dino_vitb16.safetensors") != std::string::npos);
    CHECK(std::string(e.what()).find("patch_embed.proj.weight") != std::string::npos);
  }
}
