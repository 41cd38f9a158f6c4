// The vision transformer's kernels (nn_conv1x1_rows, nn_layernorm, nn_gelu, nn_vit_embed, nn_attn_average) against
// their double twins (ref/nn_ref.h) on lavapipe, at ViT-B widths and token counts that leave
// partial workgroups, and the shape errors the host refuses.
#include <doctest/doctest.h>

#include <array>
#include <random>
#include <stdexcept>
#include <vector>

#include "nn_test_util.h"
#include "s4d/nn/attention.h"

namespace {

using namespace s4d;
using test::context;
using test::run;
using test::to_double;

}  // namespace

// Kernel nn_conv1x1_rows (nn::conv1x1 on one-row tensors).
TEST_CASE("Linear layers over tokens (one-row 1x1 convolutions) match their twin, accumulating too") {
  std::mt19937 rng(40);
  // 300 tokens: a full 256-pixel tile and a partial one; 20 outputs: a partial block of 8.
  for (const auto& [cin, cout, n] : {std::array<uint32_t, 3>{768, 20, 300}, {3072, 9, 5}}) {
    const auto x = test::random_chw(cin, 1, n, rng);
    const auto params = test::random_conv(cin, cout, 1, rng);
    const auto gx = test::upload(x);
    const auto weights = test::upload(params);
    const auto twin = ref::conv1x1(to_double(x), to_double(params.weight), to_double(params.bias), cout, false);
    const auto gpu = nn::download(context(), run([&](engine::Recorder& r) { return nn::conv1x1(r, gx, weights, false); }));
    // Float sums of 768 / 3072 products against double: measured 7.4e-7 / 2.4e-6 (accumulated: 7.1e-7 / 1.9e-6).
    INFO(cin << "->" << cout);
    test::expect_allclose(gpu, twin.v, {.of_largest = 1e-5}, "gpu");
    const auto residual = test::random_chw(cout, 1, n, rng);
    auto out = test::upload(residual, "residual");
    run([&](engine::Recorder& r) {
      nn::conv1x1_accumulate(r, gx, weights, out);
      return 0;
    });
    test::expect_allclose(nn::download(context(), out), ref::add(twin, to_double(residual)).v, {.of_largest = 1e-5}, "out");
  }
}

// Kernel nn_layernorm.
TEST_CASE("layernorm over the channels of each token matches its twin") {
  std::mt19937 rng(41);
  for (const auto& [c, n] : {std::pair<uint32_t, uint32_t>{768, 197}, {37, 5}, {3072, 1}}) {
    // An offset per token, as a residual stream carries: the centred variance must not cancel.
    auto x = test::random_chw(c, 1, n, rng, -2.0f, 2.0f);
    for (uint32_t t = 0; t < n; ++t)
      for (uint32_t ch = 0; ch < c; ++ch) x.v[size_t{ch} * n + t] += 3.0f * float(t % 3);
    const auto weight = test::random_values(c, 0.5f, 1.5f, rng), bias = test::random_values(c, -0.2f, 0.2f, rng);
    const auto gx = test::upload(x);
    const auto norm = nn::upload_norm(context(), "ln", c, weight, bias);
    const auto gpu = nn::download(context(), run([&](engine::Recorder& r) { return nn::layernorm(r, gx, norm, 1e-6f); }));
    const auto twin = ref::layernorm(to_double(x), to_double(weight), to_double(bias), 1e-6);
    // Float sums of up to 3072 values against double, offsets of up to 6 removed: measured 2.5e-6 (768 x 197).
    INFO(c << " channels, " << n << " tokens");
    test::expect_allclose(gpu, twin.v, {.of_largest = 1e-5}, "gpu");
  }
  const auto x = test::upload(test::random_chw(5, 1, 3, rng));
  const auto norm = nn::upload_norm(context(), "ln", 4, std::vector<float>(4, 1.0f), std::vector<float>(4, 0.0f));
  engine::Recorder rec(context(), "refused");
  CHECK_THROWS_AS(nn::layernorm(rec, x, norm, 1e-6f), std::invalid_argument);
  CHECK_THROWS_AS(nn::upload_norm(context(), "ln", 4, std::vector<float>(3, 1.0f), std::vector<float>(4, 0.0f)),
                  std::invalid_argument);
}

// Kernel nn_gelu.
TEST_CASE("gelu matches the exact erf GELU") {
  std::mt19937 rng(42);
  const auto x = test::random_chw(3, 7, 29, rng, -6.0f, 6.0f);
  auto gx = test::upload(x);
  run([&](engine::Recorder& r) {
    nn::gelu_inplace(r, gx);
    return 0;
  });
  const auto gpu = nn::download(context(), gx);
  const auto twin = ref::gelu(to_double(x));
  // A&S 7.1.26's erfc (absolute error 1.5e-7 on erf) in float: measured 6.1e-8 of the largest value.
  test::expect_allclose(gpu, twin.v, {.of_largest = 1e-6}, "gpu");
}

// Kernel nn_vit_embed.
TEST_CASE("vit_embed puts the class token first and adds the position embedding") {
  std::mt19937 rng(43);
  const auto patches = test::random_chw(70, 3, 5, rng), pos = test::random_chw(70, 1, 16, rng);
  const auto gpatches = test::upload(patches), gpos = test::upload(pos);
  const auto gpu = nn::download(context(), run([&](engine::Recorder& r) { return nn::vit_embed(r, gpatches, gpos); }));
  test::expect_allclose(gpu, ref::vit_embed(to_double(patches), to_double(pos)).v, {.of_largest = 1e-7}, "gpu");  // one float sum: measured 5.6e-8
  const auto wrong = test::upload(test::random_chw(70, 1, 15, rng));
  engine::Recorder rec(context(), "refused");
  CHECK_THROWS_AS(nn::vit_embed(rec, gpatches, wrong), std::invalid_argument);
}

// Kernel nn_prepend_token (nn::vit_embed with only a first token).
TEST_CASE("vit_embed with only a first token puts it before the unchanged patches") {
  std::mt19937 rng(45);
  const auto patches = test::random_chw(70, 3, 5, rng), first = test::random_chw(70, 1, 1, rng);
  const auto gpatches = test::upload(patches), gfirst = test::upload(first);
  const auto gpu = nn::download(context(), run([&](engine::Recorder& r) { return nn::vit_embed(r, gpatches, gfirst); }));
  const auto twin = ref::vit_embed(to_double(patches), to_double(first));
  REQUIRE(gpu.size() == size_t{70} * 16);
  test::expect_allclose(gpu, twin.v, {}, "gpu");  // copies
  CHECK(gpu[16] == first.v[1]);
  CHECK(gpu[17] == patches.v[15]);
}

// Kernel nn_attn_average, with nn_attn_scores and nn_softmax_rows.
TEST_CASE("a transformer's attention matches its twin whatever the chunk") {
  std::mt19937 rng(44);
  // One 64-wide head over 197 tokens (ViT-B/16 at 224x224), logits of a few units.
  const auto q = test::random_chw(64, 1, 197, rng, -0.3f, 0.3f), k = test::random_chw(64, 1, 197, rng);
  const auto v = test::random_chw(64, 1, 197, rng);
  const auto gq = test::upload(q, "q"), gk = test::upload(k, "k"), gv = test::upload(v, "v");
  const auto twin = ref::attention_average(ref::softmax_rows(ref::attention_scores(to_double(q), to_double(k)), 197),
                                           to_double(v));
  for (const size_t rows : {size_t{197}, size_t{50}, size_t{1}}) {
    const auto gpu = nn::download(context(), run([&](engine::Recorder& r) {
                                    return nn::transformer_attention(r, gq, gk, gv, rows * 197 * sizeof(float));
                                  }));
    INFO(rows);
    test::expect_allclose(gpu, twin.v, {.of_largest = 3e-6}, "gpu");  // 64-term logits, 197-term sums: measured 2.4e-7
  }
}

// Kernel nn_transpose (the attention's layouts for nn_conv1x1).
TEST_CASE("transpose swaps rows and columns exactly, as its twin") {
  std::mt19937 rng(43);
  for (const auto& [rows, cols] : {std::pair<uint32_t, uint32_t>{64, 197}, {197, 1}, {3, 130}}) {
    const auto x = test::random_chw(1, rows, cols, rng);
    const auto gx = test::upload(x);
    const auto gpu = nn::download(context(), run([&](engine::Recorder& r) { return nn::transpose(r, gx); }));
    CHECK_MESSAGE(gpu == ref::transpose(x.v, rows, cols), rows << "x" << cols);
  }
}
