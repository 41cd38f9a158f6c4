// The Gram style loss (bench/metrics/gram_loss.cpp) on lavapipe with both VGG19s: AdaIN's
// vgg_normalised (kernels nn_conv1x1, nn_conv3x3, nn_maxpool ceil mode) and torchvision's vgg19
// (nn_conv3x3_zero, nn_maxpool floor mode), against double twins on random weights the test writes
// as safetensors; hand-computed Gram matrices and losses.
#include <doctest/doctest.h>

#include <cmath>
#include <random>
#include <vector>

#include "expect_allclose.h"
#include "s4d/io/safetensors.h"
#include "s4d/metrics/gram_loss.h"
#include "torch_vgg_fixture.h"

namespace {

using namespace s4d;

const nn::VggWidths kWidths{{4, 6, 8, 8, 8}};

// G = F F^T / (C N) and the loss, written again in double from the definition.
double twin_loss(const std::vector<ref::Chw<double>>& a, const std::vector<ref::Chw<double>>& b) {
  double total = 0;
  for (size_t l = 0; l < a.size(); ++l) {
    const size_t c = a[l].c, na = size_t{a[l].h} * a[l].w, nb = size_t{b[l].h} * b[l].w;
    double s = 0;
    for (size_t i = 0; i < c; ++i)
      for (size_t j = 0; j < c; ++j) {
        double ga = 0, gb = 0;
        for (size_t p = 0; p < na; ++p) ga += a[l].v[i * na + p] * a[l].v[j * na + p];
        for (size_t p = 0; p < nb; ++p) gb += b[l].v[i * nb + p] * b[l].v[j * nb + p];
        const double d = ga / double(c * na) - gb / double(c * nb);
        s += d * d;
      }
    total += s / double(c * c);
  }
  return total;
}

}  // namespace

TEST_CASE("gram matrix and loss: hand-computed values") {
  // Constant features k over C channels and N positions: every entry is k^2 N / (C N) = k^2 / C.
  const std::vector<double> g = metrics::gram_matrix(std::vector<float>(3 * 10, 2.0f), 3, 10);
  for (double v : g) CHECK(v == doctest::Approx(4.0 / 3.0).epsilon(1e-12));
  // Channels (1, 0) and (0, 1) over 2 positions: G = I / 4.
  const std::vector<double> e = metrics::gram_matrix({1, 0, 0, 1}, 2, 2);
  CHECK(e == std::vector<double>{0.25, 0, 0, 0.25});
  // Loss of G = I/4 against 0: mean of squares = (2 x 1/16) / 4 = 1/32, plus a second layer [1] vs [3]: 4.
  const metrics::GramSet a{{2, 1}, {e, {1.0}}}, b{{2, 1}, {{0, 0, 0, 0}, {3.0}}};
  CHECK(metrics::gram_loss(a, b) == doctest::Approx(1.0 / 32 + 4).epsilon(1e-12));
  CHECK(metrics::gram_loss(a, a) == 0.0);
}

// Kernels nn_conv1x1, nn_conv3x3, nn_maxpool (vgg_normalised).
TEST_CASE("gram loss on vgg_normalised matches its double twin; 0 for identical images") {
  std::mt19937 rng(31);
  test::ScratchDir dir("gram_normalised");
  const test::NetParams vgg = test::random_vgg(kWidths, 5, rng);
  test::write_params(dir / "vgg_normalised.safetensors", vgg);
  const metrics::GramStyleLoss loss(test::context(), io::SafetensorsFile(dir / "vgg_normalised.safetensors"),
                                    metrics::GramBackbone::vgg_normalised, kWidths);
  // Frame and style of different sizes: Gram matrices make them comparable. 17 and 18 keep relu5_1 >= 2x2.
  const io::ImageF frame = test::random_image(20, 18, rng), style = test::random_image(24, 17, rng);
  const double gpu = loss(frame, style);
  const double one[3] = {1, 1, 1}, zero[3] = {0, 0, 0};
  std::vector<ref::Chw<double>> ta, tb;
  for (int level = 1; level <= 5; ++level) {
    ta.push_back(test::twin_encode(vgg, test::image_chw(frame, one, zero), level));
    tb.push_back(test::twin_encode(vgg, test::image_chw(style, one, zero), level));
  }
  const double twin = twin_loss(ta, tb);
  REQUIRE(std::isfinite(gpu));
  CHECK(twin > 0);
  // Float features through 5 levels, squared twice (Gram, then the loss): measured 1.1e-6 relative
  // (lavapipe, Mesa 22.3.6; the loss is a small difference of Gram entries here, 1.3e-4).
  CHECK(std::abs(gpu - twin) <= 1e-5 * twin);
  CHECK(std::abs(loss(frame, frame)) < 1e-15);
}

// Kernels nn_conv3x3_zero, nn_maxpool (floor mode).
TEST_CASE("gram loss on torchvision vgg19 matches its double twin") {
  std::mt19937 rng(32);
  test::ScratchDir dir("gram_vgg19");
  const test::NetParams vgg = test::random_torch_vgg(kWidths, true, rng);
  test::write_params(dir / "vgg19.safetensors", vgg);
  const metrics::GramStyleLoss loss(test::context(), io::SafetensorsFile(dir / "vgg19.safetensors"),
                                    metrics::GramBackbone::torchvision_vgg19, kWidths);
  const io::ImageF frame = test::random_image(20, 18, rng), style = test::random_image(17, 16, rng);
  const double gpu = loss(frame, style);
  double mul[3], add[3];
  for (int c = 0; c < 3; ++c) {
    mul[c] = 1.0 / metrics::kImagenetStd[c];
    add[c] = -metrics::kImagenetMean[c] / metrics::kImagenetStd[c];
  }
  const std::vector<int> taps = {1, 6, 11, 20, 29};
  const double twin = twin_loss(test::twin_torch_vgg(vgg, true, test::image_chw(frame, mul, add), taps),
                                test::twin_torch_vgg(vgg, true, test::image_chw(style, mul, add), taps));
  REQUIRE(std::isfinite(gpu));
  CHECK(twin > 0);
  CHECK(std::abs(gpu - twin) <= 1e-6 * twin);  // measured 1.2e-7 relative (lavapipe, Mesa 22.3.6)
}

// Constant frames (docs/kernel-extremes.md): every feature map is constant per channel (black gives
// the biases' ReLUs), so Gram matrices are outer products of channel values.
TEST_CASE("gram loss on black, white and constant frames is finite and the twin's") {
  std::mt19937 rng(33);
  test::ScratchDir dir("gram_constant");
  const test::NetParams vgg = test::random_vgg(kWidths, 5, rng);
  test::write_params(dir / "vgg_normalised.safetensors", vgg);
  const metrics::GramStyleLoss loss(test::context(), io::SafetensorsFile(dir / "vgg_normalised.safetensors"),
                                    metrics::GramBackbone::vgg_normalised, kWidths);
  auto constant = [](float value) { return io::ImageF{20, 18, 3, std::vector<float>(20 * 18 * 3, value)}; };
  const double one[3] = {1, 1, 1}, zero[3] = {0, 0, 0};
  auto twin_features = [&](const io::ImageF& im) {
    std::vector<ref::Chw<double>> f;
    for (int level = 1; level <= 5; ++level) f.push_back(test::twin_encode(vgg, test::image_chw(im, one, zero), level));
    return f;
  };
  for (const auto& [a, b] : {std::pair{0.0f, 1.0f}, {0.0f, 0.5f}, {1.0f, 0.25f}}) {
    CAPTURE(a);
    CAPTURE(b);
    const double gpu = loss(constant(a), constant(b)), twin = twin_loss(twin_features(constant(a)), twin_features(constant(b)));
    CHECK(twin > 0);
    // As the random frames' 1e-5 relative: measured worst 7.6e-7 (lavapipe, Mesa 22.3.6).
    test::expect_allclose(std::vector<double>{gpu}, std::vector<double>{twin}, {.rtol = 1e-5}, "gram loss");
    CHECK(std::abs(loss(constant(a), constant(a))) < 1e-15);
  }
}
