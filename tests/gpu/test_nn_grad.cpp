// The network layers' backward kernels (shaders/nn/*_bwd.comp, nn_conv_wgrad, nn_channel_dots,
// nn_mse) against their double CPU twins (ref/nn_grad_ref.h) on lavapipe, at sizes that leave
// partial workgroups and channel blocks, reflected borders on 2- and 3-pixel sides, several
// weight-gradient chunks, and pooling ties; plus the shape errors the host refuses.
#include <doctest/doctest.h>

#include <array>
#include <random>
#include <stdexcept>
#include <vector>

#include "nn_test_util.h"
#include "s4d/engine/buffer_from.h"
#include "s4d/nn/layers_grad.h"
#include "s4d/ref/nn_grad_ref.h"

namespace {

using namespace s4d;
using test::context;
using test::run;
using test::to_double;

}  // namespace

// Kernels nn_conv3x3_bwd_input, nn_conv1x1_bwd_input, nn_conv3x3_wgrad, nn_conv1x1_wgrad, nn_wgrad_reduce.
TEST_CASE("convolution input, weight and bias gradients match their twins") {
  std::mt19937 rng(21);
  // 11 input channels: a partial block of 8; 40x37 = 1480 pixels: two weight-gradient chunks of 27 rows.
  for (const auto& [cin, cout, h, w] :
       {std::array<uint32_t, 4>{11, 6, 9, 13}, {3, 5, 2, 2}, {4, 3, 3, 2}, {5, 9, 40, 37}}) {
    const auto x = test::random_chw(cin, h, w, rng);
    const auto dy = test::random_chw(cout, h, w, rng);
    const auto gdy = test::upload(dy, "dy");
    const auto gx = test::upload(x);
    for (const uint32_t k : {3u, 1u}) {
      const auto params = test::random_conv(cin, cout, k, rng);
      const auto weights = test::upload(params);
      const auto prior = test::random_chw(cin, h, w, rng);
      const auto gprior = test::upload(prior, "prior");
      auto [dx, dw, db] = run([&](engine::Recorder& r) {
        nn::Tensor into = test::upload(prior, "dx");
        nn::conv_backward_input_accumulate(r, gdy, weights, into);
        nn::ConvGrads g = nn::zero_conv_grads(r, weights);
        nn::conv_backward_weights(r, gx, gdy, weights, g, false);
        nn::conv_backward_weights(r, gx, gdy, weights, g, true);  // twice: the accumulate flag doubles it
        return std::tuple{std::move(into), std::move(g.weight), std::move(g.bias)};
      });
      auto twin_dx = k == 3 ? ref::conv3x3_bwd_input(to_double(dy), to_double(params.weight), cin)
                            : ref::conv1x1_bwd_input(to_double(dy), to_double(params.weight), cin);
      for (size_t i = 0; i < twin_dx.v.size(); ++i) twin_dx.v[i] += prior.v[i];
      const auto twin_w = ref::conv_wgrad(to_double(x), to_double(dy), k);
      std::vector<double> w2(twin_w.weight), b2(twin_w.bias);
      for (double& e : w2) e *= 2;
      for (double& e : b2) e *= 2;
      INFO(cin << "->" << cout << " " << h << "x" << w << " k " << k);
      // Float sums of up to 9 x 9 products against double: measured 1.3e-7.
      test::expect_allclose(nn::download(context(), dx), twin_dx.v, {.of_largest = 2e-6}, "dx");
      // Float sums over up to 1480 pixels in two chunks: measured 7.9e-7 (weights), 5.1e-7 (bias).
      test::expect_allclose(context().download<float>(dw, w2.size()), w2, {.of_largest = 2e-6}, "dw");
      test::expect_allclose(context().download<float>(db, b2.size()), b2, {.of_largest = 2e-6}, "db");
      const auto fresh = nn::download(context(), run([&](engine::Recorder& r) { return nn::conv_backward_input(r, gdy, weights); }));
      for (size_t i = 0; i < twin_dx.v.size(); ++i) twin_dx.v[i] -= prior.v[i];
      test::expect_allclose(fresh, twin_dx.v, {.of_largest = 2e-6}, "fresh");
    }
  }
}

// Kernels nn_relu_bwd, nn_upsample_bwd, nn_maxpool_bwd.
TEST_CASE("ReLU, upsampling and max-pooling gradients match their twins, pooling ties included") {
  std::mt19937 rng(22);
  const auto y = ref::relu(test::random_chw(5, 7, 9, rng));  // about half zeros
  const auto dy = test::random_chw(5, 7, 9, rng);
  const auto relu = nn::download(context(), run([&](engine::Recorder& r) {
    nn::Tensor g = test::upload(dy, "dy");
    nn::relu_backward(r, g, test::upload(y, "y"));
    return g;
  }));
  test::expect_allclose(relu, ref::relu_bwd(to_double(dy), to_double(y)).v, {}, "relu");  // exact copies and zeros
  const auto du = test::random_chw(5, 14, 18, rng);
  const auto up = nn::download(context(), run([&](engine::Recorder& r) { return nn::upsample2_backward(r, test::upload(du)); }));
  // Sums of 4 floats: measured 7.5e-8.
  test::expect_allclose(up, ref::upsample2_bwd(to_double(du)).v, {.of_largest = 1e-6}, "up");
  // Odd sizes (edge windows of 2 and 1 values) and ReLU zeros: tied windows of zeros everywhere.
  const auto px = y;
  const auto dp = test::random_chw(5, 4, 5, rng);
  const auto pool = nn::download(context(), run([&](engine::Recorder& r) {
    return nn::maxpool2_backward(r, test::upload(px), test::upload(dp, "dy"));
  }));
  test::expect_allclose(pool, ref::maxpool2_ceil_bwd(to_double(px), to_double(dp)).v, {}, "pool");  // copies
}

// Kernels nn_channel_dots, nn_mean_std_bwd (both modes), nn_squares_over_sum_bwd.
TEST_CASE("channel statistics, normalisation and sum(x^2)/sum(x) gradients match their twins") {
  std::mt19937 rng(23);
  const float eps = 1e-5f;
  // 300 values per channel: several passes of the 64-wide reductions.
  const auto x = test::random_chw(6, 15, 20, rng, 0.1f, 2.0f);
  const auto dy = test::random_chw(6, 15, 20, rng);
  const auto prior = test::random_chw(6, 15, 20, rng);
  const auto dstats = test::random_values(12, -1, 1, rng);
  const auto da = test::random_chw(6, 1, 1, rng);
  auto [stats, gstats, gnorm, gsos] = run([&](engine::Recorder& r) {
    const nn::Tensor gx = test::upload(x);
    engine::Buffer st = nn::mean_std(r, gx, eps);
    nn::Tensor a = test::upload(prior, "dx stats");
    nn::mean_std_backward(r, gx, st, engine::buffer_from(context(), "dstats", std::span<const float>(dstats)), a);
    nn::Tensor b = test::upload(prior, "dx normalise");
    nn::normalise_backward(r, gx, st, nn::normalise(r, gx, st), test::upload(dy, "dy"), b);
    nn::Tensor c = nn::squares_over_sum_backward(r, gx, test::upload(da, "da"));
    return std::tuple{std::move(st), std::move(a), std::move(b), std::move(c)};
  });
  const auto xd = to_double(x);
  const auto st = to_double(context().download<float>(stats, 12));  // the twin starts from the GPU's statistics
  auto twin_stats = ref::mean_std_bwd(xd, st, to_double(dstats));
  auto twin_norm = ref::normalise_bwd(xd, st, to_double(dy));
  for (size_t i = 0; i < prior.v.size(); ++i) twin_stats.v[i] += prior.v[i], twin_norm.v[i] += prior.v[i];
  // Float element-wise maths and sums over 300 values: measured 5.3e-8, 9.1e-8, 9.6e-8.
  test::expect_allclose(nn::download(context(), gstats), twin_stats.v, {.of_largest = 1e-6}, "gstats");
  test::expect_allclose(nn::download(context(), gnorm), twin_norm.v, {.of_largest = 1e-6}, "gnorm");
  test::expect_allclose(nn::download(context(), gsos), ref::squares_over_sum_bwd(xd, to_double(da.v)).v, {.of_largest = 2e-6}, "gsos");
}

// Kernel nn_mse.
TEST_CASE("squared error adds scale (a - b) to the gradient and sums (a - b)^2 over partial workgroups") {
  std::mt19937 rng(24);
  const auto a = test::random_values(1000, -1, 1, rng), b = test::random_values(1000, -1, 1, rng);
  const auto prior = test::random_values(1000, -1, 1, rng);
  auto [grad, partials] = run([&](engine::Recorder& r) {
    engine::Buffer g = engine::buffer_from(context(), "grad", std::span<const float>(prior));
    engine::Buffer p = nn::squared_error(r, engine::buffer_from(context(), "a", std::span<const float>(a)),
                                         engine::buffer_from(context(), "b", std::span<const float>(b)), g, 1000, 0.25f);
    return std::pair{std::move(g), std::move(p)};
  });
  std::vector<double> twin(1000);
  for (size_t i = 0; i < twin.size(); ++i) twin[i] = prior[i] + 0.25 * (double(a[i]) - b[i]);
  test::expect_allclose(context().download<float>(grad, 1000), twin, {.of_largest = 1e-6}, "grad");  // one float FMA: measured 5.3e-8
  const double sum = ref::squared_error(to_double(a), to_double(b));
  CHECK(nn::squared_error_value(context(), partials) == doctest::Approx(sum).epsilon(1e-6));  // float sums of 1000 squares: measured below 1e-7
}

// Kernel nn_tv_l1.
TEST_CASE("L1 total variation adds weight dTV/dx to the gradient and sums the TV over partial workgroups") {
  std::mt19937 rng(26);
  const auto x = test::random_chw(3, 9, 11, rng);  // 297 values: a partial workgroup
  const auto prior = test::random_chw(3, 9, 11, rng);
  auto [grad, partials] = run([&](engine::Recorder& r) {
    nn::Tensor g = test::upload(prior, "grad");
    engine::Buffer p = nn::tv_l1(r, test::upload(x), g, 0.5f);
    return std::pair{std::move(g), std::move(p)};
  });
  auto twin = ref::tv_l1_bwd(to_double(x));
  for (size_t i = 0; i < twin.v.size(); ++i) twin.v[i] = prior.v[i] + 0.5 * twin.v[i];
  test::expect_allclose(nn::download(context(), grad), twin.v, {.of_largest = 1e-6}, "grad");  // sums of 4 signs, one FMA: measured 4.0e-8
  // Float sums of 580 magnitudes: within the printed 329.135.
  CHECK(nn::squared_error_value(context(), partials) == doctest::Approx(ref::tv_l1(to_double(x))).epsilon(1e-6));
}

// Kernels nn_avgpool3, nn_avgpool3_bwd, nn_channel_max, nn_selfsim_bwd.
TEST_CASE("3x3 average pooling, its gradient and the self-similarity term match their twins") {
  std::mt19937 rng(27);
  const auto x = test::random_chw(3, 9, 11, rng);
  const auto dy = test::random_chw(3, 7, 9, rng);
  const auto v = test::random_chw(5, 9, 13, rng, 0.05f, 1.0f);  // 117 values per channel: two reduction passes
  const auto prior = test::random_chw(5, 9, 13, rng);
  auto [pooled, dpool, grad, value] = run([&](engine::Recorder& r) {
    nn::Tensor g = test::upload(prior, "grad");
    engine::Buffer val = nn::selfsim(r, test::upload(v, "v"), g, 0.5f);
    return std::tuple{nn::avgpool3(r, test::upload(x)), nn::avgpool3_backward(r, test::upload(dy, "dy")), std::move(g),
                      std::move(val)};
  });
  test::expect_allclose(nn::download(context(), pooled), ref::avgpool3(to_double(x)).v, {.of_largest = 1e-6}, "pooled");  // sums of 9: measured 9.7e-8
  test::expect_allclose(nn::download(context(), dpool), ref::avgpool3_bwd(to_double(dy)).v, {.of_largest = 1e-6}, "dpool");  // measured 1.2e-7
  auto twin = ref::selfsim_bwd(to_double(v));
  for (size_t i = 0; i < twin.v.size(); ++i) twin.v[i] = prior.v[i] + 0.5 / 5 * twin.v[i];
  test::expect_allclose(nn::download(context(), grad), twin.v, {.of_largest = 1e-5}, "grad");  // float sums over 585 values: measured 3.0e-8
  // The value from the same float sums: equal to the printed 4.98725.
  CHECK(context().download<float>(value, 1)[0] == doctest::Approx(ref::selfsim(to_double(v))).epsilon(1e-5));
}

TEST_CASE("backward layers refuse mismatched shapes before recording") {
  std::mt19937 rng(25);
  {
    const auto weights = test::upload(test::random_conv(4, 6, 3, rng));
    engine::Recorder r(context(), "refused");
    const nn::Tensor dy = nn::make_tensor(context(), "dy", 5, 4, 4);
    CHECK_THROWS_AS(nn::conv_backward_input(r, dy, weights), std::invalid_argument);
    const nn::Tensor one_row = nn::make_tensor(context(), "dy", 6, 1, 4);
    CHECK_THROWS_AS(nn::conv_backward_input(r, one_row, weights), std::invalid_argument);
    const nn::Tensor x = nn::make_tensor(context(), "x", 4, 4, 4);
    CHECK_THROWS_AS(nn::maxpool2_backward(r, x, nn::make_tensor(context(), "dy", 4, 3, 2)), std::invalid_argument);
    CHECK_THROWS_AS(nn::upsample2_backward(r, nn::make_tensor(context(), "dy", 4, 3, 4)), std::invalid_argument);
    const auto five = test::upload(test::random_conv(4, 6, 5, rng));
    nn::ConvGrads g{nn::make_tensor(context(), "dw", 1, 1, 600).buffer, nn::make_tensor(context(), "db", 1, 1, 6).buffer};
    CHECK_THROWS_AS(nn::conv_backward_weights(r, x, nn::make_tensor(context(), "dy", 6, 4, 4), five, g, false),
                    std::invalid_argument);
  }
  context().run(engine::Recorder(context(), "flush"));  // frees what the unsubmitted recorder kept alive
}

