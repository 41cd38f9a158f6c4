// The network layers (shaders/nn) against their double CPU twins (ref/nn_ref.h) on lavapipe, at
// sizes that leave partial tiles, partial output-channel blocks and partial workgroups, plus the
// shape errors the host refuses before recording.
#include <doctest/doctest.h>

#include <array>
#include <random>
#include <stdexcept>
#include <vector>

#include "nn_test_util.h"
#include "s4d/engine/buffer_from.h"

namespace {

using namespace s4d;
using test::context;
using test::run;
using test::to_double;

}  // namespace

// Kernel nn_conv3x3.
TEST_CASE("conv3x3 with reflection padding matches its twin, with and without ReLU") {
  std::mt19937 rng(1);
  // 13x9: two partial tiles each way; 11 outputs: a partial block of 8.
  for (const auto& [cin, cout, h, w] : {std::array<uint32_t, 4>{5, 11, 9, 13}, {3, 8, 2, 2}, {16, 3, 8, 8}}) {
    const auto x = test::random_chw(cin, h, w, rng);
    const auto params = test::random_conv(cin, cout, 3, rng);
    const auto gx = test::upload(x);
    const auto weights = test::upload(params);
    for (const bool relu : {false, true}) {
      const auto gpu =
          nn::download(context(), run([&](engine::Recorder& r) { return nn::conv3x3(r, gx, weights, relu); }));
      const auto twin = ref::conv3x3(to_double(x), to_double(params.weight), to_double(params.bias), cout, relu);
      // Float sums of at most 144 products of O(1) terms against double: measured 2.0e-7.
      INFO(cin << "->" << cout << " " << h << "x" << w << " relu " << relu);
      test::expect_allclose(gpu, twin.v, {.of_largest = 2e-6}, "gpu");
    }
  }
}

// Kernel nn_conv3x3_zero.
TEST_CASE("conv3x3 with zero padding matches its twin, down to 1x1 images") {
  std::mt19937 rng(11);
  for (const auto& [cin, cout, h, w] :
       {std::array<uint32_t, 4>{5, 11, 9, 13}, {3, 8, 1, 1}, {4, 3, 1, 5}, {16, 9, 8, 8}}) {
    const auto x = test::random_chw(cin, h, w, rng);
    const auto params = test::random_conv(cin, cout, 3, rng);
    const auto gx = test::upload(x);
    const auto weights = test::upload(params);
    for (const bool relu : {false, true}) {
      const auto gpu =
          nn::download(context(), run([&](engine::Recorder& r) { return nn::conv3x3_zero_pad(r, gx, weights, relu); }));
      const auto twin = ref::conv3x3_zero_pad(to_double(x), to_double(params.weight), to_double(params.bias), cout, relu);
      // Float sums of at most 144 products of O(1) terms against double: measured 2.1e-7.
      INFO(cin << "->" << cout << " " << h << "x" << w << " relu " << relu);
      test::expect_allclose(gpu, twin.v, {.of_largest = 2e-6}, "gpu");
    }
  }
  // The zero border differs from the reflected one: the two variants must disagree at the edges.
  const auto x = test::random_chw(2, 4, 4, rng, 0.5f, 1.0f);
  const auto params = test::random_conv(2, 8, 3, rng);
  const auto gx = test::upload(x);
  const auto weights = test::upload(params);
  const auto zero = nn::download(context(), run([&](engine::Recorder& r) { return nn::conv3x3_zero_pad(r, gx, weights, false); }));
  const auto reflect = ref::conv3x3(to_double(x), to_double(params.weight), to_double(params.bias), 8, false);
  CHECK_FALSE(test::allclose_report(zero, reflect.v, {.of_largest = 1e-2}, "zero padding").ok);
}

// Kernel nn_conv_strided.
TEST_CASE("strided convolutions of any kernel size (AlexNet's 11x11 stride 4, 5x5, a ViT's 16x16 patches, ResNet's 7x7 stride 2) match their twin") {
  std::mt19937 rng(13);
  struct Case {
    uint32_t cin, cout, k, stride, pad, h, w;
  };
  // Then a ViT's 16x16 stride-16 patch embedding, the image's last 5 rows and 2 columns unseen, and
  // ResNet's (CKDN) 7x7 stride-2 stem, 3x3 stride-2 and 1x1 stride-2 convolutions.
  for (const Case c : {Case{3, 5, 11, 4, 2, 35, 31}, Case{4, 6, 5, 1, 2, 9, 7}, Case{6, 3, 3, 1, 1, 5, 4}, Case{2, 3, 3, 2, 0, 7, 8},
                       Case{3, 9, 16, 16, 0, 37, 50}, Case{3, 4, 7, 2, 3, 13, 10}, Case{5, 3, 3, 2, 1, 9, 6},
                       Case{6, 4, 1, 2, 0, 7, 9}}) {
    const auto x = test::random_chw(c.cin, c.h, c.w, rng);
    const auto params = test::random_conv(c.cin, c.cout, c.k, rng);
    const auto gx = test::upload(x);
    const auto weights = test::upload(params);
    for (const bool relu : {false, true}) {
      const auto gpu = nn::download(
          context(), run([&](engine::Recorder& r) { return nn::conv_strided(r, gx, weights, c.stride, c.pad, relu); }));
      const auto twin = ref::conv2d(to_double(x), to_double(params.weight), to_double(params.bias), c.cout, c.k, c.stride, c.pad, relu);
      // Float sums of at most 768 products against double: measured 6.0e-7 (the 11x11 stride-4 case).
      INFO("k " << c.k << " stride " << c.stride << " " << c.h << "x" << c.w);
      test::expect_allclose(gpu, twin.v, {.of_largest = 2e-6}, "gpu");
    }
  }
  // cin * k * k past llvmpipe's loop cap is refused before recording.
  const auto wide = test::random_conv(600, 1, 11, rng);
  const auto gw = test::upload(wide);
  const auto x = test::upload(test::random_chw(600, 11, 11, rng));
  engine::Recorder rec(context(), "refused");
  CHECK_THROWS_AS(nn::conv_strided(rec, x, gw, 4, 2, true), std::invalid_argument);
}

TEST_CASE("conv3x3 over 1024 input channels stays under llvmpipe's loop cap") {
  // Were the kernel rows, taps, strip pixels and channel block runtime loops, each invocation would
  // run over 100,000 iterations and llvmpipe would end it early: this test then fails (checked
  // with [[dont_unroll]]).
  std::mt19937 rng(2);
  const auto x = test::random_chw(1024, 3, 2, rng);
  const auto params = test::random_conv(1024, 8, 3, rng);
  const auto gx = test::upload(x);
  const auto weights = test::upload(params);
  const auto gpu =
      nn::download(context(), run([&](engine::Recorder& r) { return nn::conv3x3(r, gx, weights, false); }));
  const auto twin = ref::conv3x3(to_double(x), to_double(params.weight), to_double(params.bias), 8, false);
  test::expect_allclose(gpu, twin.v, {.of_largest = 1e-5}, "gpu");  // 9216 float products per output: measured 5.8e-7
}

// Kernel nn_conv1x1.
TEST_CASE("conv1x1 matches its twin, as a Linear layer too, and accumulates into its output") {
  std::mt19937 rng(3);
  const auto x = test::random_chw(7, 5, 6, rng);
  const auto params = test::random_conv(7, 10, 1, rng);
  const auto gx = test::upload(x);
  const auto weights = test::upload(params);
  const auto twin = ref::conv1x1(to_double(x), to_double(params.weight), to_double(params.bias), 10, true);
  const auto gpu = nn::download(context(), run([&](engine::Recorder& r) { return nn::conv1x1(r, gx, weights, true); }));
  test::expect_allclose(gpu, twin.v, {.of_largest = 2e-6}, "gpu");  // 7 products: measured 7.7e-8

  const auto v = test::random_chw(33, 1, 1, rng);
  const auto linear = test::random_conv(33, 20, 1, rng);
  const auto gv = test::upload(v);
  const auto lw = test::upload(linear);
  const auto lin = nn::download(context(), run([&](engine::Recorder& r) { return nn::conv1x1(r, gv, lw, false); }));
  const auto lin_twin = ref::conv1x1(to_double(v), to_double(linear.weight), to_double(linear.bias), 20, false);
  test::expect_allclose(lin, lin_twin.v, {.of_largest = 2e-6}, "lin");  // 33 products: measured 1.4e-7

  const auto residual = test::random_chw(10, 5, 6, rng);
  auto out = test::upload(residual, "residual");
  run([&](engine::Recorder& r) {
    nn::conv1x1_accumulate(r, gx, weights, out);
    return 0;
  });
  auto expected = ref::conv1x1(to_double(x), to_double(params.weight), to_double(params.bias), 10, false);
  for (size_t i = 0; i < expected.v.size(); ++i) expected.v[i] += residual.v[i];
  test::expect_allclose(nn::download(context(), out), expected.v, {.of_largest = 2e-6}, "out");  // measured 8.0e-8
}

// Kernels nn_relu, nn_maxpool, nn_avgpool2, nn_maxpool3s2, nn_upsample, nn_subsample2.
TEST_CASE("relu, 2x2 ceil- and floor-mode max pooling, nearest upsampling and subsampling match their twins exactly") {
  std::mt19937 rng(4);
  for (const auto& [h, w] : {std::array<uint32_t, 2>{7, 5}, {8, 6}, {1, 3}}) {
    const auto x = test::random_chw(3, h, w, rng);
    const auto gx = test::upload(x);
    const auto pooled = nn::download(context(), run([&](engine::Recorder& r) { return nn::maxpool2(r, gx); }));
    test::expect_allclose(pooled, ref::maxpool2_ceil(to_double(x)).v, {}, "pooled");
    const auto up = nn::download(context(), run([&](engine::Recorder& r) { return nn::upsample2(r, gx); }));
    test::expect_allclose(up, ref::upsample2(to_double(x)).v, {}, "up");
    const auto sub = nn::download(context(), run([&](engine::Recorder& r) { return nn::subsample2(r, gx); }));
    const auto sub_twin = ref::subsample2(to_double(x));
    REQUIRE(sub.size() == size_t{3} * ((h + 1) / 2) * ((w + 1) / 2));
    test::expect_allclose(sub, sub_twin.v, {}, "sub");
  }
  // Floor mode (torchvision's VGG) through the same kernel: odd last rows and columns are dropped.
  for (const auto& [h, w] : {std::array<uint32_t, 2>{7, 5}, {8, 6}, {2, 3}}) {
    const auto x = test::random_chw(3, h, w, rng);
    const auto gx = test::upload(x);
    const auto pooled = nn::download(context(), run([&](engine::Recorder& r) { return nn::maxpool2_floor(r, gx); }));
    test::expect_allclose(pooled, ref::maxpool2_floor(to_double(x)).v, {}, "pooled");
    // AvgPool2d(2) (CLIP's ModifiedResNet), floor mode as well.
    const auto averaged = nn::download(context(), run([&](engine::Recorder& r) { return nn::avgpool2(r, gx); }));
    const auto average_twin = ref::avgpool2(to_double(x));
    REQUIRE(averaged.size() == size_t{3} * (h / 2) * (w / 2));
    test::expect_allclose(averaged, average_twin.v, {.of_largest = 1e-6}, "averaged");  // three float sums and a division by 4: measured 1.1e-7
  }
  {
    engine::Recorder rec(context(), "refused");
    CHECK_THROWS_AS(nn::avgpool2(rec, test::upload(test::random_chw(2, 1, 4, rng))), std::invalid_argument);
  }
  // 3x3 stride 2 (AlexNet, kernel nn_maxpool3s2): floor((in - 3) / 2) + 1 outputs.
  for (const auto& [h, w] : {std::array<uint32_t, 2>{7, 9}, {3, 3}, {8, 6}}) {
    const auto x = test::random_chw(3, h, w, rng);
    const auto gx = test::upload(x);
    const auto pooled = nn::download(context(), run([&](engine::Recorder& r) { return nn::maxpool3s2(r, gx); }));
    test::expect_allclose(pooled, ref::maxpool3s2(to_double(x)).v, {}, "pooled");
  }
  // With padding 1 (ResNet's stem): floor((in - 1) / 2) + 1 outputs, border windows partly outside;
  // all-negative inputs so a padded zero winning would show.
  for (const auto& [h, w] : {std::array<uint32_t, 2>{7, 9}, {1, 2}, {8, 6}}) {
    const auto x = test::random_chw(3, h, w, rng, -2.0f, -0.5f);
    const auto gx = test::upload(x);
    const auto pooled = nn::download(context(), run([&](engine::Recorder& r) { return nn::maxpool3s2(r, gx, 1); }));
    const auto twin = ref::maxpool3s2(to_double(x), 1);
    REQUIRE(pooled.size() == twin.v.size());
    CHECK(twin.h == (h - 1) / 2 + 1);
    test::expect_allclose(pooled, twin.v, {}, "pooled");
  }
  auto x = test::random_chw(2, 9, 11, rng);
  auto gx = test::upload(x);
  run([&](engine::Recorder& r) {
    nn::relu_inplace(r, gx);
    return 0;
  });
  test::expect_allclose(nn::download(context(), gx), ref::relu(to_double(x)).v, {}, "gx");
}

// Kernel nn_l2pool.
TEST_CASE("DISTS's L2 pooling matches its twin and the hand-computed values of a constant image") {
  std::mt19937 rng(12);
  for (const auto& [h, w] : {std::array<uint32_t, 2>{7, 5}, {8, 6}, {1, 1}, {1, 3}}) {
    const auto x = test::random_chw(3, h, w, rng);
    const auto gx = test::upload(x);
    const auto pooled = nn::download(context(), run([&](engine::Recorder& r) { return nn::l2pool(r, gx); }));
    // 9 float squares summed, then a square root: measured 6.4e-8.
    INFO(h << "x" << w);
    test::expect_allclose(pooled, ref::l2pool(to_double(x), 1e-12).v, {.of_largest = 1e-6}, "pooled");
  }
  // Constant 0.8 on 4x4: every output window's weights sum to 1 inside, so sqrt(0.64) = 0.8, except
  // where the zero padding cuts the window: the top-left output sees rows and columns 0, 1 with
  // weights (2 + 1) / 4 each way, sqrt(9/16 * 0.64) = 0.6; the others lose one side: sqrt(12/16 * 0.64).
  ref::Chw<float> c(1, 4, 4);
  c.v.assign(16, 0.8f);
  const auto gc = test::upload(c);
  const auto out = nn::download(context(), run([&](engine::Recorder& r) { return nn::l2pool(r, gc); }));
  REQUIRE(out.size() == 4);
  CHECK(out[0] == doctest::Approx(0.6).epsilon(1e-6));
  CHECK(out[1] == doctest::Approx(std::sqrt(0.75 * 0.64)).epsilon(1e-6));
  CHECK(out[3] == doctest::Approx(0.8).epsilon(1e-6));
}

// Kernels nn_channel_stats (both variants).
TEST_CASE("channel mean and std (unbiased + eps) and MCC's sum(x^2)/sum(x) match their twins") {
  std::mt19937 rng(5);
  // 300x300: each of the 64 invocations sums about 1400 values before the workgroup sum.
  for (const auto& [c, h, w] : {std::array<uint32_t, 3>{3, 17, 23}, {2, 300, 300}, {5, 1, 2}}) {
    const auto x = test::random_chw(c, h, w, rng, -0.5f, 1.5f);
    const auto gx = test::upload(x);
    const auto stats =
        context().download<float>(run([&](engine::Recorder& r) { return nn::mean_std(r, gx, 1e-5f); }), 2 * size_t{c});
    // Float partial sums against double: measured 2.0e-7 (300x300).
    const std::vector<double> stats_twin = ref::mean_std(to_double(x), 1e-5);
    test::expect_allclose(stats, stats_twin, {.of_largest = 2e-6}, "stats");
    // global_average: the means alone, as a [c, 1, 1] tensor.
    const auto means = nn::download(context(), run([&](engine::Recorder& r) { return nn::global_average(r, gx); }));
    REQUIRE(means.size() == c);
    test::expect_allclose(means, std::vector<double>(stats_twin.begin(), stats_twin.begin() + c), {.of_largest = 2e-6}, "means");  // as the means above
    const auto a = nn::download(context(), run([&](engine::Recorder& r) { return nn::squares_over_sum(r, gx); }));
    test::expect_allclose(a, ref::squares_over_sum(to_double(x)), {.of_largest = 2e-6}, "a");  // measured 3.7e-7 (300x300)
  }
}

// Kernels nn_adain, nn_scale_channels, nn_blend.
TEST_CASE("adain, its content blend, normalisation, channel scaling and blending match their twins") {
  std::mt19937 rng(6);
  const auto content = test::random_chw(6, 7, 9, rng);
  const auto style = test::random_chw(6, 4, 5, rng, 0.0f, 3.0f);
  const auto gc = test::upload(content);
  const auto gs = test::upload(style);
  const auto cs = ref::mean_std(to_double(content), 1e-5), ss = ref::mean_std(to_double(style), 1e-5);
  for (const float alpha : {1.0f, 0.3f}) {
    const auto gpu = nn::download(context(), run([&](engine::Recorder& r) {
                                    const auto c_stats = nn::mean_std(r, gc);
                                    const auto s_stats = nn::mean_std(r, gs);
                                    return nn::adain(r, gc, c_stats, s_stats, alpha);
                                  }));
    // The float statistics' 1e-7 error carried through: measured 1.1e-7.
    test::expect_allclose(gpu, ref::adain(to_double(content), cs, ss, double{alpha}).v, {.of_largest = 2e-6}, "gpu");
  }
  const auto normalised = nn::download(context(), run([&](engine::Recorder& r) {
                                         const auto c_stats = nn::mean_std(r, gc);
                                         return nn::normalise(r, gc, c_stats);
                                       }));
  test::expect_allclose(normalised, ref::normalise(to_double(content), cs).v, {.of_largest = 2e-6}, "normalised");  // measured 7.7e-8

  const auto factors = test::random_values(6, -2.0f, 2.0f, rng);
  auto scaled = test::upload(content);
  const auto gf = engine::buffer_from(context(), "factors", factors);
  run([&](engine::Recorder& r) {
    nn::scale_channels(r, scaled, gf);
    return 0;
  });
  const auto scaled_twin = ref::scale_channels(to_double(content), to_double(factors));
  test::expect_allclose(nn::download(context(), scaled), scaled_twin.v, {.of_largest = 1e-7}, "scaled");  // one rounding: measured 3.0e-8

  const auto other = test::random_chw(6, 7, 9, rng);
  const auto go = test::upload(other, "other");
  const auto blended = nn::download(context(), run([&](engine::Recorder& r) { return nn::blend(r, gc, go, 0.3f); }));
  std::vector<double> blend_twin(content.v.size());
  for (size_t i = 0; i < blend_twin.size(); ++i) blend_twin[i] = 0.3 * content.v[i] + 0.7 * other.v[i];
  test::expect_allclose(blended, blend_twin, {.of_largest = 2e-7}, "blended");  // two products and a sum in float: measured 6.2e-8
  // subtract (CKDN's branch difference): one rounding of a - b.
  const auto diff = nn::download(context(), run([&](engine::Recorder& r) { return nn::subtract(r, gc, go); }));
  std::vector<double> diff_twin(content.v.size());
  for (size_t i = 0; i < diff_twin.size(); ++i) diff_twin[i] = double(content.v[i]) - double(other.v[i]);
  test::expect_allclose(diff, diff_twin, {.of_largest = 1e-7}, "diff");  // measured 0 (float a - b is the exact difference rounded once)
}

TEST_CASE("layers refuse mismatched shapes before recording anything") {
  std::mt19937 rng(7);
  const auto weights = test::upload(test::random_conv(4, 8, 3, rng), "enc 2");
  const auto three = test::upload(test::random_chw(3, 4, 4, rng));
  const auto thin = test::upload(test::random_chw(4, 1, 5, rng));
  const auto single = test::upload(test::random_chw(4, 1, 1, rng));
  engine::Recorder rec(context(), "errors");
  CHECK_THROWS_WITH_AS(nn::conv3x3(rec, three, weights, true), "conv enc 2: expects 4 input channels, got [3, 4, 4]",
                       std::invalid_argument);
  CHECK_THROWS_WITH_AS(nn::conv3x3(rec, thin, weights, true),
                       "conv enc 2: reflection padding needs H, W >= 2, got [4, 1, 5]", std::invalid_argument);
  CHECK_THROWS_WITH_AS(nn::conv1x1(rec, thin, weights, true), "conv enc 2: is not a 1x1 convolution",
                       std::invalid_argument);
  CHECK_THROWS_WITH_AS(nn::mean_std(rec, single), "mean_std: needs at least 2 values per channel, got [4, 1, 1]",
                       std::invalid_argument);
  CHECK_THROWS_AS(nn::upload_conv(context(), "bad", 4, 8, 3, std::vector<float>(10), std::vector<float>(8)),
                  std::invalid_argument);
}
