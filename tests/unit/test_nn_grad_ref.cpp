// The network layers' backward twins (ref/nn_grad_ref.h) against central finite differences of the
// forward twins (ref/nn_ref.h) in double: L = sum r * f(x) with a random r, so each backward gets
// dy = r. Sizes leave reflected border rows on both sides (h, w = 2 and 3 included) and odd pooling
// edges; pooling ties follow PyTorch's first-maximum rule.
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <random>
#include <vector>

#include "s4d/ref/nn_grad_ref.h"
#include "fd_check.h"

namespace {

using s4d::ref::Chw;
using s4d::test::fd_error;

Chw<double> random_chw(uint32_t c, uint32_t h, uint32_t w, std::mt19937& rng, double lo = -1, double hi = 1) {
  std::uniform_real_distribution<double> u(lo, hi);
  Chw<double> t(c, h, w);
  for (double& e : t.v) e = u(rng);
  return t;
}

std::vector<double> random_vec(size_t n, std::mt19937& rng, double lo = -1, double hi = 1) {
  std::uniform_real_distribution<double> u(lo, hi);
  std::vector<double> v(n);
  for (double& e : v) e = u(rng);
  return v;
}

}  // namespace

TEST_CASE("conv3x3 (reflection) and conv1x1 input, weight and bias gradients match finite differences") {
  std::mt19937 rng(1);
  for (const std::array<uint32_t, 4>& shape : {std::array<uint32_t, 4>{3, 4, 5, 6}, {2, 3, 2, 2}, {2, 2, 3, 2}, {1, 2, 3, 3}}) {
    const uint32_t cin = shape[0], cout = shape[1], h = shape[2], w = shape[3];  // lambdas below capture these
    Chw<double> x = random_chw(cin, h, w, rng);
    std::vector<double> weight = random_vec(size_t{cout} * cin * 9, rng), bias = random_vec(cout, rng);
    const Chw<double> r = random_chw(cout, h, w, rng);
    auto f3 = [&] { return s4d::ref::conv3x3(x, weight, bias, cout, false).v; };
    const auto g3 = s4d::ref::conv_wgrad(x, r, 3);
    // Central differences of a function linear in each variable: only rounding, measured 1.2e-9.
    CHECK(fd_error(x.v, f3, r.v, s4d::ref::conv3x3_bwd_input(r, weight, cin).v) < 1e-8);
    CHECK(fd_error(weight, f3, r.v, g3.weight) < 1e-8);
    CHECK(fd_error(bias, f3, r.v, g3.bias) < 1e-8);
    std::vector<double> w1 = random_vec(size_t{cout} * cin, rng);
    auto f1 = [&] { return s4d::ref::conv1x1(x, w1, bias, cout, false).v; };
    const auto g1 = s4d::ref::conv_wgrad(x, r, 1);
    CHECK(fd_error(x.v, f1, r.v, s4d::ref::conv1x1_bwd_input(r, w1, cin).v) < 1e-8);
    CHECK(fd_error(w1, f1, r.v, g1.weight) < 1e-8);
    CHECK(fd_error(bias, f1, r.v, g1.bias) < 1e-8);
  }
}

TEST_CASE("ReLU, nearest upsampling and ceil-mode max pooling gradients match finite differences") {
  std::mt19937 rng(2);
  Chw<double> x = random_chw(3, 5, 7, rng);  // odd sizes: the pooling's edge windows cover 2 or 1 values
  const Chw<double> ry = random_chw(3, 5, 7, rng);
  auto relu = [&] { return s4d::ref::relu(x).v; };
  // Away from 0 ReLU is locally linear; rounding only: measured 3.4e-10 (upsample 3.5e-10, pool 6.3e-10).
  CHECK(fd_error(x.v, relu, ry.v, s4d::ref::relu_bwd(ry, s4d::ref::relu(x)).v) < 1e-8);
  const Chw<double> ru = random_chw(3, 10, 14, rng);
  auto up = [&] { return s4d::ref::upsample2(x).v; };
  CHECK(fd_error(x.v, up, ru.v, s4d::ref::upsample2_bwd(ru).v) < 1e-8);
  const Chw<double> rp = random_chw(3, 3, 4, rng);
  auto pool = [&] { return s4d::ref::maxpool2_ceil(x).v; };
  CHECK(fd_error(x.v, pool, rp.v, s4d::ref::maxpool2_ceil_bwd(x, rp).v) < 1e-8);
  // Ties (ReLU zeros): the window's first value in row-major order takes the gradient, as PyTorch.
  Chw<double> ties(1, 3, 3);
  ties.at(0, 1, 0) = ties.at(0, 1, 1) = 0.5;  // window (0, 0) ties 0.5 with 0.5; the others tie zeros
  Chw<double> dy(1, 2, 2);
  dy.v = {1, 2, 3, 4};
  CHECK(s4d::ref::maxpool2_ceil_bwd(ties, dy).v == std::vector<double>{0, 0, 2, 1, 0, 0, 3, 0, 4});
}

TEST_CASE("channel mean/std, normalisation and MCC's sum(x^2)/sum(x) gradients match finite differences") {
  std::mt19937 rng(3);
  Chw<double> x = random_chw(4, 3, 5, rng, 0.1, 2.0);  // positive: sum(x) stays away from 0
  const double eps = 1e-5;
  const std::vector<double> rs = random_vec(8, rng);
  auto stats = [&] { return s4d::ref::mean_std(x, eps); };
  const auto st = s4d::ref::mean_std(x, eps);
  // Smooth functions, step 1e-6: measured 2.4e-9 (mean/std), 1.9e-9 (normalise), 1.6e-9 (a).
  CHECK(fd_error(x.v, stats, rs, s4d::ref::mean_std_bwd(x, st, rs).v) < 1e-7);
  const Chw<double> rn = random_chw(4, 3, 5, rng);
  auto norm = [&] { return s4d::ref::normalise(x, s4d::ref::mean_std(x, eps)).v; };
  CHECK(fd_error(x.v, norm, rn.v, s4d::ref::normalise_bwd(x, st, rn).v) < 1e-7);
  const std::vector<double> ra = random_vec(4, rng);
  auto sos = [&] { return s4d::ref::squares_over_sum(x); };
  CHECK(fd_error(x.v, sos, ra, s4d::ref::squares_over_sum_bwd(x, ra).v) < 1e-7);
}

TEST_CASE("the L1 total variation's gradient matches finite differences") {
  std::mt19937 rng(4);
  Chw<double> x = random_chw(2, 5, 6, rng);
  const std::vector<double> one{1.0};
  auto tv = [&] { return std::vector<double>{s4d::ref::tv_l1(x)}; };
  // Piecewise linear; random values keep every difference away from 0: rounding only, measured 2.9e-9.
  CHECK(fd_error(x.v, tv, one, s4d::ref::tv_l1_bwd(x).v) < 1e-8);
}

TEST_CASE("the 3x3 average pooling's and the self-similarity's gradients match finite differences") {
  std::mt19937 rng(5);
  Chw<double> x = random_chw(2, 5, 6, rng);
  const Chw<double> r = random_chw(2, 3, 4, rng);
  auto pool = [&] { return s4d::ref::avgpool3(x).v; };
  CHECK(fd_error(x.v, pool, r.v, s4d::ref::avgpool3_bwd(r).v) < 1e-8);  // linear: measured 5.5e-10
  Chw<double> v = random_chw(3, 2, 3, rng, 0.1, 1.0);  // positive and distinct: the maxima stay put
  const std::vector<double> one{1.0};
  auto sim = [&] { return std::vector<double>{s4d::ref::selfsim(v)}; };
  CHECK(fd_error(v.v, sim, one, s4d::ref::selfsim_bwd(v).v) < 1e-7);  // smooth for distinct maxima: measured 5.0e-9
}
