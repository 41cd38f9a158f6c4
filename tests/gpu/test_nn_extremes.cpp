// The transformer's elementwise and row kernels (nn_layernorm, nn_softmax_rows, nn_gelu) at
// activations of 1e4 (docs/kernel-extremes.md): outputs finite and equal to the double twins fed the
// same float inputs.
#include <doctest/doctest.h>

#include <algorithm>
#include <random>
#include <vector>

#include "expect_allclose.h"
#include "nn_test_util.h"
#include "s4d/nn/attention.h"

namespace {

using namespace s4d;
using test::context;
using test::run;
using test::to_double;

}  // namespace

TEST_CASE("layernorm of tokens at 1e4: spread, constant, offset by 1e4 and alternating, like the twin") {
  std::mt19937 rng(70);
  constexpr uint32_t c = 768, n = 4;
  ref::Chw<float> x(c, 1, n);
  const std::vector<float> spread = test::random_values(c, -1e4f, 1e4f, rng), noise = test::random_values(c, -1, 1, rng);
  for (uint32_t ch = 0; ch < c; ++ch) {
    x.v[size_t{ch} * n + 0] = spread[ch];
    x.v[size_t{ch} * n + 1] = 1e4f;  // no variance: the output is the bias (eps keeps 1/sqrt finite)
    x.v[size_t{ch} * n + 2] = 1e4f + noise[ch];  // a unit spread on a 1e4 offset: the mean must not cancel it
    x.v[size_t{ch} * n + 3] = ch % 2 ? 1e4f : -1e4f;
  }
  const auto weight = test::random_values(c, 0.5f, 1.5f, rng), bias = test::random_values(c, -0.2f, 0.2f, rng);
  const auto gx = test::upload(x);
  const auto norm = nn::upload_norm(context(), "ln", c, weight, bias);
  const auto gpu = nn::download(context(), run([&](engine::Recorder& r) { return nn::layernorm(r, gx, norm, 1e-6f); }));
  const auto twin = ref::layernorm(to_double(x), to_double(weight), to_double(bias), 1e-6);
  // Float sums of 768 shifted values against double: measured worst 1.8e-6 on lavapipe (Mesa 22.3.6).
  test::expect_allclose(gpu, twin.v, {.atol = 1e-5, .rtol = 1e-5}, "layernorm at 1e4");
}

TEST_CASE("softmax of rows with logits of +-1e4: spread, all equal and one-hot, like the twin") {
  std::mt19937 rng(71);
  constexpr uint32_t n = 300;  // longer than a workgroup
  ref::Chw<float> s(1, 3, n);
  const std::vector<float> spread = test::random_values(n, -1e4f, 1e4f, rng);
  for (uint32_t j = 0; j < n; ++j) {
    s.v[j] = spread[j];
    s.v[n + j] = 1e4f;                          // uniform 1/300
    s.v[2 * n + j] = j == 7 ? 1e4f : -1e4f;     // exp(-2e4) underflows to 0: exactly one-hot
  }
  auto gs = test::upload(s, "scores");
  run([&](engine::Recorder& r) {
    nn::softmax_rows(r, gs);
    return 0;
  });
  // Float exp of arguments shifted by the row maximum: measured worst 8.1e-11 (the uniform row).
  test::expect_allclose(nn::download(context(), gs), ref::softmax_rows(to_double(s.v), n), {.atol = 1e-7, .rtol = 1e-5},
                        "softmax at 1e4");
}

TEST_CASE("gelu at +-1e4 and beyond is x and -0 at the ends, like the twin") {
  std::mt19937 rng(72);
  ref::Chw<float> x(1, 1, 64);
  x.v = test::random_values(64, -1e4f, 1e4f, rng);
  const std::vector<float> ends = {1e4f, -1e4f, 1e30f, -1e30f, 3e38f, -3e38f, 0.0f, -10.0f};
  std::copy(ends.begin(), ends.end(), x.v.begin());
  auto gx = test::upload(x);
  run([&](engine::Recorder& r) {
    nn::gelu_inplace(r, gx);
    return 0;
  });
  // x exactly for large x, -0 or a tiny tail for large -x: measured worst 1.5e-24 (at x = -10,
  // A&S 7.1.26's relative error on a value of 8e-23).
  test::expect_allclose(nn::download(context(), gx), ref::gelu(to_double(x)).v, {.atol = 1e-7, .rtol = 1e-6},
                        "gelu at 1e4");
}
