// The CCPL kernels (nn_ccpl_gather(_bwd), nn_l2norm_cols(_bwd), nn_patchnce) and one whole level
// (nn::record_ccpl_level: heads, scores and products through the reused kernels) against their
// double twins (ref/ccpl_ref.h) on lavapipe, at sample counts that leave partial workgroups and with
// repeated and clamped indices; the sampling's rules; the shape errors the host refuses.
#include <doctest/doctest.h>

#include <array>
#include <random>
#include <set>
#include <stdexcept>
#include <vector>

#include "nn_test_util.h"
#include "s4d/engine/buffer_from.h"
#include "s4d/nn/ccpl.h"
#include "s4d/ref/ccpl_ref.h"

namespace {

using namespace s4d;
using test::context;
using test::run;
using test::to_double;

std::vector<uint32_t> joined(const nn::CcplSamples& s) {
  std::vector<uint32_t> v(s.anchor);
  v.insert(v.end(), s.neighbour.begin(), s.neighbour.end());
  return v;
}

}  // namespace

TEST_CASE("CCPL's samples: distinct interior anchors, row-major neighbours, jitter of at most 1, clamped") {
  std::mt19937_64 rng(5);
  for (const bool jitter : {false, true}) {
    const nn::CcplSamples s = nn::draw_ccpl_samples(6, 7, 16, jitter, rng);
    REQUIRE(s.anchor.size() == 128);
    std::set<uint32_t> distinct;
    const int offsets[8] = {-8, -7, -6, -1, 1, 6, 7, 8};
    for (size_t a = 0; a < 16; ++a) {
      const uint32_t at = s.anchor[8 * a];
      distinct.insert(at);
      CHECK(at / 7 >= 1);
      CHECK(at / 7 <= 4);
      CHECK(at % 7 >= 1);
      CHECK(at % 7 <= 5);
      for (int t = 0; t < 8; ++t) {
        CHECK(s.anchor[8 * a + t] == at);
        const int delta = int(s.neighbour[8 * a + t]) - int(at) - offsets[t];
        if (jitter) CHECK(std::abs(delta) <= 1);
        else CHECK(delta == 0);
      }
    }
    CHECK(distinct.size() == 16);
  }
  // A 3x3 level has one interior position: its jittered neighbours reach index 0 and 8 at most.
  const nn::CcplSamples one = nn::draw_ccpl_samples(3, 3, 1, true, rng);
  for (const uint32_t n : one.neighbour) CHECK(n <= 8);
  CHECK_THROWS_WITH_AS(nn::draw_ccpl_samples(3, 3, 2, false, rng), "ccpl: 2 anchors on a 3x3 level, which has 1 interior positions",
                       std::invalid_argument);
  CHECK_THROWS_AS(nn::draw_ccpl_samples(2, 9, 1, false, rng), std::invalid_argument);
}

TEST_CASE("the CCPL gather, the column normalisation and PatchNCE match their twins") {
  std::mt19937 rng(41);
  std::mt19937_64 draw(41);
  const auto f = test::random_chw(11, 9, 10, rng);
  const nn::CcplSamples samples = nn::draw_ccpl_samples(9, 10, 9, true, draw);  // 72 samples: a partial workgroup
  const std::vector<uint32_t> pairs = joined(samples);
  const engine::Buffer gpairs = engine::buffer_from(context(), "pairs", pairs);
  const auto dout = test::random_chw(11, 1, 72, rng);
  const auto prior = test::random_chw(11, 9, 10, rng);
  auto [out, df] = run([&](engine::Recorder& r) {
    nn::Tensor into = test::upload(prior, "df");
    nn::ccpl_gather_backward(r, test::upload(dout, "dout"), gpairs, into);
    return std::pair{nn::ccpl_gather(r, test::upload(f), gpairs, 72), std::move(into)};
  });
  test::expect_allclose(nn::download(context(), out), ref::ccpl_gather(to_double(f), samples.anchor, samples.neighbour).v, {.of_largest = 1e-6}, "out");  // one float difference: measured 3.2e-8
  auto twin_df = ref::ccpl_gather_bwd(to_double(dout), samples.anchor, samples.neighbour, 9, 10);
  for (size_t i = 0; i < twin_df.v.size(); ++i) twin_df.v[i] += prior.v[i];
  test::expect_allclose(nn::download(context(), df), twin_df.v, {.of_largest = 1e-6}, "df");  // sums of a few values: measured 4.6e-8

  const auto x = test::random_chw(37, 1, 70, rng), dy = test::random_chw(37, 1, 70, rng);
  auto [y, dx] = run([&](engine::Recorder& r) {
    const nn::Tensor gx = test::upload(x);
    return std::pair{nn::l2norm_columns(r, gx), nn::l2norm_columns_backward(r, gx, test::upload(dy, "dy"))};
  });
  // Float sums over 37 channels: measured 1.2e-7 (forward), 1.6e-7 (backward).
  test::expect_allclose(nn::download(context(), y), ref::l2norm_cols(to_double(x)).v, {.of_largest = 2e-6}, "y");
  test::expect_allclose(nn::download(context(), dx), ref::l2norm_cols_bwd(to_double(x), to_double(dy)).v, {.of_largest = 2e-6}, "dx");

  const auto scores = test::random_chw(1, 70, 70, rng);  // cosines in [-1, 1]: logits up to 1 / tau
  const float tau = 0.07f, scale = 0.3f;
  auto nce = run([&](engine::Recorder& r) { return nn::patchnce(r, test::upload(scores, "scores"), tau, scale); });
  const auto twin = ref::patchnce_rows(to_double(scores.v), 70, 1.0 / double(tau), double(scale));
  // exp of logits up to 14 in float: measured 5.5e-8 (losses), 1.7e-7 (gradient).
  test::expect_allclose(context().download<float>(nce.loss, 70), twin.loss, {.of_largest = 5e-6}, "nce.loss");
  test::expect_allclose(nn::download(context(), nce.grad), twin.grad, {.of_largest = 5e-6}, "nce.grad");
  CHECK_THROWS_AS(run([&](engine::Recorder& r) { return nn::patchnce(r, test::upload(dy, "dy"), tau, scale); }), std::invalid_argument);
}

TEST_CASE("one CCPL level (heads, normalisation, PatchNCE and back) matches its twin") {
  std::mt19937 rng(42);
  std::mt19937_64 draw(42);
  const uint32_t c = 24, out = c / 4;
  const auto fq = test::random_chw(c, 10, 12, rng, 0.0f, 1.0f), fk = test::random_chw(c, 10, 12, rng, 0.0f, 1.0f);
  const auto first = test::random_conv(c, c, 1, rng), second = test::random_conv(c, out, 1, rng);
  const nn::CcplHead head{test::upload(first, "head 0"), test::upload(second, "head 2")};
  const ref::CcplHeadRef<double> twin_head{c, out, to_double(first.weight), to_double(first.bias), to_double(second.weight),
                                           to_double(second.bias)};
  for (const bool jitter : {false, true}) {
    const nn::CcplSamples samples = nn::draw_ccpl_samples(10, 12, 16, jitter, draw);
    const auto prior = test::random_chw(c, 10, 12, rng);
    auto [loss, dfq, g0w, g0b, g1w, g1b] = run([&](engine::Recorder& r) {
      nn::Tensor into = test::upload(prior, "dfq");
      nn::ConvGrads g[2] = {nn::zero_conv_grads(r, head.first), nn::zero_conv_grads(r, head.second)};
      engine::Buffer l = nn::record_ccpl_level(r, head, test::upload(fq, "fq"), test::upload(fk, "fk"), samples, 0.07f, 4.0f, into, g);
      return std::tuple{std::move(l), std::move(into), std::move(g[0].weight), std::move(g[0].bias), std::move(g[1].weight),
                        std::move(g[1].bias)};
    });
    const auto twin = ref::ccpl_level(to_double(fq), to_double(fk), samples.anchor, samples.neighbour, twin_head, 0.07, 4.0, true);
    double value = 0;
    for (const float v : context().download<float>(loss, 128)) value += 4.0 * v / 128;
    auto twin_dfq = twin.grads.dfq;
    for (size_t i = 0; i < twin_dfq.v.size(); ++i) twin_dfq.v[i] += prior.v[i];
    INFO("jitter " << jitter);
    // Float through two Linear layers, the normalisation and exp(logits / 0.07): measured 3.2e-8
    // (value), 3.4e-7 (features), 6.6e-7 (heads).
    CHECK(std::abs(value - twin.value) / twin.value < 1e-6);
    test::expect_allclose(nn::download(context(), dfq), twin_dfq.v, {.of_largest = 1e-5}, "dfq");
    test::expect_allclose(context().download<float>(g0w, c * c), twin.grads.first.weight, {.of_largest = 1e-5}, "g0w");
    test::expect_allclose(context().download<float>(g0b, c), twin.grads.first.bias, {.of_largest = 1e-5}, "g0b");
    test::expect_allclose(context().download<float>(g1w, out * c), twin.grads.second.weight, {.of_largest = 1e-5}, "g1w");
    test::expect_allclose(context().download<float>(g1b, out), twin.grads.second.bias, {.of_largest = 1e-5}, "g1b");
  }
  // Weight 0 without head gradients (a set that only logs the term): the same losses, dq untouched.
  {
    const nn::CcplSamples samples = nn::draw_ccpl_samples(10, 12, 16, true, draw);
    const auto prior = test::random_chw(c, 10, 12, rng);
    auto [loss, dfq] = run([&](engine::Recorder& r) {
      nn::Tensor into = test::upload(prior, "dfq");
      engine::Buffer l = nn::record_ccpl_level(r, head, test::upload(fq, "fq"), test::upload(fk, "fk"), samples, 0.07f, 0.0f, into, nullptr);
      return std::pair{std::move(l), std::move(into)};
    });
    const auto twin = ref::ccpl_level(to_double(fq), to_double(fk), samples.anchor, samples.neighbour, twin_head, 0.07, 1.0, false);
    double value = 0;
    for (const float v : context().download<float>(loss, 128)) value += v / 128;
    CHECK(std::abs(value - twin.value) / twin.value < 1e-6);  // as above
    CHECK(nn::download(context(), dfq) == prior.v);
  }
  nn::CcplSamples bad = nn::draw_ccpl_samples(10, 12, 2, false, draw);
  bad.neighbour[3] = 120;
  nn::Tensor dfq = test::upload(fq, "dfq");
  CHECK_THROWS_WITH_AS(run([&](engine::Recorder& r) {
                         return nn::record_ccpl_level(r, head, test::upload(fq, "fq"), test::upload(fk, "fk"), bad, 0.07f, 1.0f, dfq, nullptr);
                       }),
                       "ccpl: sample index 120 outside the level [24, 10, 12]", std::invalid_argument);
}
