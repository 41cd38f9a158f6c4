// The CCPL twins (ref/ccpl_ref.h) against central finite differences in double: the gather's and
// the L2 normalisation's adjoints, PatchNCE's gradient w.r.t. its scores, and one whole level (heads,
// normalisation, PatchNCE) w.r.t. q's features and the heads' weights, with repeated and clamped
// indices as HGST's jitter makes them.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <random>
#include <vector>

#include "s4d/ref/ccpl_ref.h"
#include "fd_check.h"

namespace {

using s4d::ref::Chw;
using s4d::test::fd_error;

std::vector<double> random_vec(size_t n, std::mt19937& rng, double lo = -1, double hi = 1) {
  std::uniform_real_distribution<double> u(lo, hi);
  std::vector<double> v(n);
  for (double& e : v) e = u(rng);
  return v;
}

Chw<double> random_chw(uint32_t c, uint32_t h, uint32_t w, std::mt19937& rng) {
  Chw<double> t(c, h, w);
  t.v = random_vec(t.v.size(), rng);
  return t;
}

// 3 anchors of a 5x6 plane with their 8 neighbours, some jittered onto each other and clamped at 0.
const std::vector<uint32_t> anchors = {7, 7, 7, 7, 7, 7, 7, 7, 14, 14, 14, 14, 14, 14, 14, 14, 22, 22, 22, 22, 22, 22, 22, 22};
const std::vector<uint32_t> neighbours = {0, 0, 2, 6, 8, 12, 13, 14, 7, 8, 9, 13, 15, 19, 20, 20, 15, 16, 17, 21, 23, 27, 28, 29};

}  // namespace

TEST_CASE("the CCPL gather's and the column L2 normalisation's gradients match finite differences") {
  std::mt19937 rng(31);
  Chw<double> f = random_chw(3, 5, 6, rng);
  const Chw<double> r = random_chw(3, 1, 24, rng);
  auto gather = [&] { return s4d::ref::ccpl_gather(f, anchors, neighbours).v; };
  // Linear: rounding only, measured 2.0e-10.
  CHECK(fd_error(f.v, gather, r.v, s4d::ref::ccpl_gather_bwd(r, anchors, neighbours, 5, 6).v) < 1e-8);
  Chw<double> x = random_chw(5, 1, 7, rng);
  const Chw<double> ry = random_chw(5, 1, 7, rng);
  auto norm = [&] { return s4d::ref::l2norm_cols(x).v; };
  // Smooth away from 0, step 1e-6: measured 2.9e-10.
  CHECK(fd_error(x.v, norm, ry.v, s4d::ref::l2norm_cols_bwd(x, ry).v) < 1e-7);
}

TEST_CASE("PatchNCE's gradient w.r.t. the scores matches finite differences and its value the cross-entropy") {
  std::mt19937 rng(32);
  const uint32_t s = 6;
  std::vector<double> scores = random_vec(size_t{s} * s, rng);
  const double inv_tau = 1 / 0.07, scale = 0.7;
  auto total = [&] {
    double sum = 0;
    for (const double l : s4d::ref::patchnce_rows(scores, s, inv_tau, scale).loss) sum += scale * l;
    return std::vector<double>{sum};
  };
  const auto nce = s4d::ref::patchnce_rows(scores, s, inv_tau, scale);
  // Logits up to 14 (1 / tau): exp keeps them smooth; measured 3.3e-10.
  CHECK(fd_error(scores, total, {1.0}, nce.grad) < 1e-7);
  // Row 0 by hand: -log(e^{P00/tau} / sum_j e^{P0j/tau}).
  double sum = 0;
  for (uint32_t j = 0; j < s; ++j) sum += std::exp(scores[j] * inv_tau);
  CHECK(nce.loss[0] == doctest::Approx(-std::log(std::exp(scores[0] * inv_tau) / sum)).epsilon(1e-12));
}

TEST_CASE("one CCPL level's gradients w.r.t. q's features and the heads match finite differences") {
  std::mt19937 rng(33);
  const uint32_t c = 8, out = 2;
  Chw<double> fq = random_chw(c, 5, 6, rng);
  const Chw<double> fk = random_chw(c, 5, 6, rng);
  s4d::ref::CcplHeadRef<double> head{c, out, random_vec(c * c, rng, -0.5, 0.5), random_vec(c, rng, -0.1, 0.3),
                                     random_vec(size_t{out} * c, rng, -0.5, 0.5), random_vec(out, rng, -0.1, 0.1)};
  const double tau = 0.07, weight = 1.5;
  for (const bool k_in_heads : {false, true}) {
    const auto level = s4d::ref::ccpl_level(fq, fk, anchors, neighbours, head, tau, weight, k_in_heads);
    auto value = [&] { return std::vector<double>{s4d::ref::ccpl_level(fq, fk, anchors, neighbours, head, tau, weight, false).value}; };
    INFO("k in heads " << k_in_heads);
    // Through ReLU kinks that random weights keep away from the 1e-6 steps: measured 1.0e-9 (features), 4.2e-10 (heads).
    CHECK(fd_error(fq.v, value, {1.0}, level.grads.dfq.v) < 1e-7);
    if (k_in_heads) {  // the heads' gradients through both q and k: both sides of the value move with them
      CHECK(fd_error(head.w1, value, {1.0}, level.grads.first.weight) < 1e-7);
      CHECK(fd_error(head.b1, value, {1.0}, level.grads.first.bias) < 1e-7);
      CHECK(fd_error(head.w2, value, {1.0}, level.grads.second.weight) < 1e-7);
      CHECK(fd_error(head.b2, value, {1.0}, level.grads.second.bias) < 1e-7);
    }
  }
}
