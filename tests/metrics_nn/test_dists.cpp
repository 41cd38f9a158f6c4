// DISTS (bench/metrics/dists.cpp) on lavapipe: torchvision VGG16 with L2 pooling on the GPU
// (kernels nn_conv3x3_zero, nn_l2pool) and the host statistics, against a double twin with its own
// statistics on random weights the test writes as safetensors; hand-computed values; identity,
// symmetry and the weight-file errors.
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "s4d/io/safetensors.h"
#include "s4d/metrics/dists.h"
#include "s4d/metrics/rgb_tensor.h"
#include "torch_vgg_fixture.h"

namespace {

using namespace s4d;

const nn::VggWidths kWidths{{4, 6, 8, 8, 8}};
constexpr int64_t kChannels = 3 + 4 + 6 + 8 + 8 + 8;

// DISTS from the definition, in double: stage 0 raw, then the twin's taps.
double twin_dists(const test::NetParams& vgg, const std::vector<float>& alpha, const std::vector<float>& beta,
                  const io::ImageF& a, const io::ImageF& b) {
  const double one[3] = {1, 1, 1}, zero[3] = {0, 0, 0};
  double mul[3], add[3];
  for (int c = 0; c < 3; ++c) {
    mul[c] = 1.0 / metrics::kImagenetStd[c];
    add[c] = -metrics::kImagenetMean[c] / metrics::kImagenetStd[c];
  }
  const std::vector<int> taps = {3, 8, 15, 22, 29};
  std::vector<ref::Chw<double>> fa = {test::image_chw(a, one, zero)}, fb = {test::image_chw(b, one, zero)};
  for (auto& t : test::twin_torch_vgg(vgg, false, test::image_chw(a, mul, add), taps, true)) fa.push_back(t);
  for (auto& t : test::twin_torch_vgg(vgg, false, test::image_chw(b, mul, add), taps, true)) fb.push_back(t);
  double wsum = 0;
  for (size_t k = 0; k < alpha.size(); ++k) wsum += double(alpha[k]) + double(beta[k]);
  double d1 = 0, d2 = 0;
  size_t k = 0;
  for (size_t s = 0; s < fa.size(); ++s) {
    const size_t n = size_t{fa[s].h} * fa[s].w;
    for (size_t c = 0; c < fa[s].c; ++c, ++k) {
      double mx = 0, my = 0, xx = 0, yy = 0, xy = 0;
      for (size_t i = 0; i < n; ++i) {
        const double x = fa[s].v[c * n + i], y = fb[s].v[c * n + i];
        mx += x / double(n), my += y / double(n);
        xx += x * x / double(n), yy += y * y / double(n), xy += x * y / double(n);
      }
      const double s1 = (2 * mx * my + 1e-6) / (mx * mx + my * my + 1e-6);
      const double s2 = (2 * (xy - mx * my) + 1e-6) / ((xx - mx * mx) + (yy - my * my) + 1e-6);
      d1 += double(alpha[k]) / wsum * s1;
      d2 += double(beta[k]) / wsum * s2;
    }
  }
  return 1 - (d1 + d2);
}

// Random VGG16 weights and DISTS alpha / beta written as the bench reads them.
struct RandomDists {
  test::NetParams vgg;
  std::vector<float> alpha, beta;
};

RandomDists write_random_dists(const std::filesystem::path& dir, std::mt19937& rng) {
  RandomDists w{test::random_torch_vgg(kWidths, false, rng), {}, {}};
  test::write_params(dir / "vgg16.safetensors", w.vgg);
  w.alpha = test::random_values(kChannels, 0.01f, 0.03f, rng);
  w.beta = test::random_values(kChannels, 0.0f, 0.02f, rng);
  io::write_safetensors(dir / "dists.safetensors",
                        {{"alpha", {1, kChannels, 1, 1}, w.alpha}, {"beta", {1, kChannels, 1, 1}, w.beta}});
  return w;
}

metrics::Dists open_dists(const std::filesystem::path& dir) {
  return metrics::Dists(test::context(), io::SafetensorsFile(dir / "vgg16.safetensors"),
                        io::SafetensorsFile(dir / "dists.safetensors"), kWidths);
}

}  // namespace

// Kernels nn_conv3x3_zero, nn_l2pool.
TEST_CASE("dists matches its double twin on random weights, is symmetric and 0 for identical images") {
  std::mt19937 rng(51);
  test::ScratchDir dir("dists");
  const RandomDists w = write_random_dists(dir.path(), rng);
  const test::NetParams& vgg = w.vgg;
  const std::vector<float>&alpha = w.alpha, &beta = w.beta;
  const metrics::Dists dists = open_dists(dir.path());
  // 19x13: odd sizes at every L2 pool; relu5_3 is 2x1.
  const io::ImageF a = test::random_image(19, 13, rng), b = test::random_image(19, 13, rng);
  const double gpu = dists(a, b), twin = twin_dists(vgg, alpha, beta, a, b);
  REQUIRE(std::isfinite(gpu));
  CHECK(twin > 0.05);
  // Float backbone against double; the statistics are in double on both sides: measured 2.7e-8
  // relative (lavapipe, Mesa 22.3.6).
  CHECK(std::abs(gpu - twin) <= 1e-6 * twin);
  CHECK(std::abs(dists(b, a) - gpu) <= 1e-12);  // symmetric term by term
  // Identical images: S1 = S2 = 1 per channel and the weights sum to 1, so 1 - 1 up to rounding
  // (measured 2.2e-16).
  CHECK(std::abs(dists(a, a)) < 1e-12);
}

TEST_CASE("dists on black and constant frames is finite and the twin's (zero variances meet the 1e-6 guards)") {
  std::mt19937 rng(52);
  test::ScratchDir dir("dists_constant");
  const RandomDists w = write_random_dists(dir.path(), rng);
  const metrics::Dists dists = open_dists(dir.path());
  auto constant = [](float v) {
    io::ImageF image{19, 13, 3, {}};
    image.data.assign(19 * 13 * 3, v);
    return image;
  };
  const io::ImageF black = constant(0.0f), grey = constant(0.5f);
  const double gpu = dists(black, grey), twin = twin_dists(w.vgg, w.alpha, w.beta, black, grey);
  REQUIRE(std::isfinite(gpu));
  // Measured 8.8e-8 relative (black against grey): the statistics of constant maps take the guards.
  CHECK(std::abs(gpu - twin) <= 1e-6 * twin);
  CHECK(twin > 0.01);
  CHECK(std::abs(dists(black, black)) < 1e-12);
}

TEST_CASE("dists: hand-computed values and the weight-file errors") {
  // One stage, one channel: constants 1 and 0 give S1 = c1 / (1 + c1) and S2 = c2 / c2 = 1; with
  // alpha = beta = 0.5, DISTS = 1 - 0.5 S1 - 0.5.
  ref::Chw<double> x(1, 2, 2), y(1, 2, 2);
  x.v.assign(4, 1.0);
  const double s1 = 1e-6 / (1 + 1e-6);
  CHECK(metrics::dists_from_features({x}, {y}, {0.5}, {0.5}) == doctest::Approx(0.5 - 0.5 * s1).epsilon(1e-12));
  // x = (1, -1, 1, -1), y = -x: means 0 (S1 = 1), var 1 each, cov -1: S2 = (-2 + c2) / (2 + c2).
  ref::Chw<double> p(1, 1, 4), q(1, 1, 4);
  p.v = {1, -1, 1, -1};
  q.v = {-1, 1, -1, 1};
  const double s2 = (-2 + 1e-6) / (2 + 1e-6);
  CHECK(metrics::dists_from_features({p}, {q}, {0.25}, {0.75}) == doctest::Approx(1 - 0.25 - 0.75 * s2).epsilon(1e-12));
  CHECK_THROWS_AS(metrics::dists_from_features({p}, {q}, {0.25, 0.1}, {0.75, 0.1}), std::invalid_argument);

  std::mt19937 rng(52);
  test::ScratchDir dir("dists_errors");
  test::write_params(dir / "vgg16.safetensors", test::random_torch_vgg(kWidths, false, rng));
  // alpha of the published width (1475) for a backbone of other widths: named with its shape.
  io::write_safetensors(dir / "bad.safetensors", {{"alpha", {1, 1475, 1, 1}, std::vector<float>(1475, 0.01f)},
                                                  {"beta", {1, 1475, 1, 1}, std::vector<float>(1475, 0.01f)}});
  try {
    metrics::Dists(test::context(), io::SafetensorsFile(dir / "vgg16.safetensors"), io::SafetensorsFile(dir / "bad.safetensors"),
                   kWidths);
    FAIL("alpha of the wrong width was accepted");
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    CHECK(what.find("bad.safetensors") != std::string::npos);
    CHECK(what.find("alpha") != std::string::npos);
  }
}
