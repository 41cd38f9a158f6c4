// The densification twin (training/ref/include/s4d/ref/densify_ref.h) on hand-built clouds: each
// rule alone, the budget's choice of what to demote, empty results, zero-count Gaussians, Adam
// moment semantics, the split geometry and the split samples' distribution.
#include <doctest/doctest.h>

#include <cmath>
#include <vector>

#include "s4d/ref/densify_ref.h"

namespace {

using s4d::ref::DensifyCounts;
using s4d::ref::DensifyState;
using S = DensifyState;

struct Rules {
  float grad_threshold = 0.0002f, dense_scale = 0.01f, min_opacity = 0.005f, max_screen_radius = 0, max_world_scale = 0;
  bool grow = true, prune = true;
};

s4d::gpu::ClassifyParams params(const Rules& r, size_t n) {
  return s4d::gpu::densify_classify_params(static_cast<uint32_t>(n), r.grad_threshold, r.dense_scale, r.min_opacity,
                                           r.max_screen_radius, r.max_world_scale, r.grow, r.prune);
}

// n Gaussians at x = i, scale 0.005 (cloned under dense_scale 0.01), opacity 0.5, identity rotation,
// no gradient; every other value distinct so copies can be traced; moments non-zero.
DensifyState cloud(size_t n) {
  DensifyState s;
  s.sh_width = 3;
  s.resize(n);
  for (size_t i = 0; i < n; ++i) {
    const float f = static_cast<float>(i);
    for (int k = 0; k < 3; ++k) {
      s.param[S::kMeans][3 * i + k] = k == 0 ? f : 0.1f * f + static_cast<float>(k);
      s.param[S::kLogScales][3 * i + k] = std::log(0.005f);
      s.param[S::kSh][3 * i + k] = 0.01f * f + 0.1f * static_cast<float>(k);
    }
    s.param[S::kQuats][4 * i] = 1;
    s.param[S::kOpacity][i] = 0;
    for (int a = 0; a < S::kAttrs; ++a)
      for (uint32_t e = 0; e < s.width(a); ++e) {
        s.m[a][i * s.width(a) + e] = 1 + f + 0.01f * static_cast<float>(e);
        s.v[a][i * s.width(a) + e] = 2 + f + 0.01f * static_cast<float>(e);
      }
    s.stat[S::kGradCount][i] = 4;
    s.stat[S::kMaxRadius][i] = 3;
  }
  return s;
}

void set_grad(DensifyState& s, size_t i, float mean_grad) { s.stat[S::kGradAccum][i] = mean_grad * s.stat[S::kGradCount][i]; }

// Output j is an exact copy of source i in every parameter.
void check_copy_of(const DensifyState& out, size_t j, const DensifyState& in, size_t i) {
  for (int a = 0; a < S::kAttrs; ++a)
    for (uint32_t e = 0; e < in.width(a); ++e) CHECK(out.param[a][j * in.width(a) + e] == in.param[a][i * in.width(a) + e]);
}

void check_moments(const DensifyState& out, size_t j, const DensifyState& in, size_t i, bool fresh) {
  for (int a = 0; a < S::kAttrs; ++a)
    for (uint32_t e = 0; e < in.width(a); ++e) {
      CHECK(out.m[a][j * in.width(a) + e] == (fresh ? 0.0f : in.m[a][i * in.width(a) + e]));
      CHECK(out.v[a][j * in.width(a) + e] == (fresh ? 0.0f : in.v[a][i * in.width(a) + e]));
    }
}

void check_stats_zero(const DensifyState& out) {
  for (const auto& s : out.stat)
    for (float x : s) CHECK(x == 0.0f);
}

}  // namespace

TEST_CASE("densify twin clones a small Gaussian with a large gradient right after itself") {
  DensifyState s = cloud(3);
  set_grad(s, 1, 0.0005f);
  DensifyCounts c;
  const DensifyState out = s4d::ref::densify(s, params({}, 3), UINT32_MAX, 7, &c);
  CHECK(c.before == 3);
  CHECK(c.cloned == 1);
  CHECK(c.split == 0);
  CHECK(c.pruned == 0);
  CHECK(c.after == 4);
  REQUIRE(out.size() == 4);
  const size_t source[4] = {0, 1, 1, 2};
  for (size_t j = 0; j < 4; ++j) {
    check_copy_of(out, j, s, source[j]);
    check_moments(out, j, s, source[j], j == 2);  // the copy's Adam moments start at zero
  }
  check_stats_zero(out);
}

TEST_CASE("densify twin splits a large Gaussian into two shrunken children sampled around it") {
  DensifyState s = cloud(3);
  // Gaussian 1: scales (1, 0.02, 0.02) rotated 90 degrees about z, so its long axis is world y.
  const float ls[3] = {0.0f, std::log(0.02f), std::log(0.02f)};
  for (int k = 0; k < 3; ++k) s.param[S::kLogScales][3 + k] = ls[k];
  const float h = std::sqrt(0.5f);
  const float q[4] = {2 * h, 0, 0, 2 * h};  // un-normalised on purpose
  for (int k = 0; k < 4; ++k) s.param[S::kQuats][4 + k] = q[k];
  set_grad(s, 1, 0.001f);
  DensifyCounts c;
  const DensifyState out = s4d::ref::densify(s, params({}, 3), UINT32_MAX, 11, &c);
  CHECK(c.split == 1);
  CHECK(c.cloned == 0);
  CHECK(c.after == 4);
  REQUIRE(out.size() == 4);
  check_copy_of(out, 0, s, 0);
  check_copy_of(out, 3, s, 2);
  const float log16 = static_cast<float>(std::log(1.6));
  for (size_t j : {size_t{1}, size_t{2}}) {
    check_moments(out, j, s, 1, true);
    for (int k = 0; k < 3; ++k) CHECK(out.param[S::kLogScales][3 * j + k] == ls[k] - log16);
    for (int k = 0; k < 4; ++k) CHECK(out.param[S::kQuats][4 * j + k] == q[k]);
    CHECK(out.param[S::kOpacity][j] == s.param[S::kOpacity][1]);
    // The offset is R (s * n): along y up to s_x |n_x|, across it at most 0.02 |n|.
    const std::array<float, 3> n = s4d::ref::densify_split_normals(11, 1, static_cast<uint32_t>(j - 1));
    const float dx = out.param[S::kMeans][3 * j] - s.param[S::kMeans][3];
    const float dy = out.param[S::kMeans][3 * j + 1] - s.param[S::kMeans][4];
    const float dz = out.param[S::kMeans][3 * j + 2] - s.param[S::kMeans][5];
    CHECK(dy == doctest::Approx(n[0]).epsilon(1e-5));
    CHECK(dx == doctest::Approx(-0.02f * n[1]).epsilon(1e-4));
    CHECK(dz == doctest::Approx(0.02f * n[2]).epsilon(1e-4));
  }
  CHECK(out.param[S::kMeans][3 * 1 + 1] != out.param[S::kMeans][3 * 2 + 1]);  // different samples per child
  check_stats_zero(out);
}

TEST_CASE("densify twin's split samples are standard normal and depend on the seed") {
  double sum[3] = {}, sq[3] = {};
  const int n = 20000;
  for (uint32_t i = 0; i < n / 2; ++i)
    for (uint32_t child = 0; child < 2; ++child) {
      const auto x = s4d::ref::densify_split_normals(5, i, child);
      for (int k = 0; k < 3; ++k) sum[k] += x[k], sq[k] += double{x[k]} * x[k];
    }
  for (int k = 0; k < 3; ++k) {
    CHECK(std::abs(sum[k] / n) < 0.03);            // 4 standard errors of the mean
    CHECK(std::abs(sq[k] / n - 1) < 0.05);         // about 5 standard errors of the variance
  }
  CHECK(s4d::ref::densify_split_normals(5, 3, 0)[0] != s4d::ref::densify_split_normals(6, 3, 0)[0]);
}

TEST_CASE("densify twin prunes by opacity, screen radius and world scale, each only when enabled") {
  DensifyState s = cloud(4);
  s.param[S::kOpacity][1] = -6;  // sigmoid = 0.0025 < 0.005
  s.stat[S::kMaxRadius][2] = 30;
  s.param[S::kLogScales][3 * 3 + 2] = std::log(0.5f);
  Rules r;
  r.grow = false;
  DensifyCounts c;
  DensifyState out = s4d::ref::densify(s, params(r, 4), UINT32_MAX, 0, &c);
  CHECK(c.pruned == 1);  // screen and world rules are off at 0
  REQUIRE(out.size() == 3);
  check_copy_of(out, 1, s, 2);
  r.max_screen_radius = 20;
  out = s4d::ref::densify(s, params(r, 4), UINT32_MAX, 0, &c);
  CHECK(c.pruned == 2);
  REQUIRE(out.size() == 2);
  check_copy_of(out, 1, s, 3);
  r.max_world_scale = 0.1f;
  out = s4d::ref::densify(s, params(r, 4), UINT32_MAX, 0, &c);
  CHECK(c.pruned == 3);
  REQUIRE(out.size() == 1);
  check_copy_of(out, 0, s, 0);
  check_moments(out, 0, s, 0, false);
  r.prune = false;
  out = s4d::ref::densify(s, params(r, 4), UINT32_MAX, 0, &c);
  CHECK(c.pruned == 0);
  CHECK(out.size() == 4);
}

TEST_CASE("densify twin prunes new entries too: a clone of a Gaussian too large on screen survives it") {
  DensifyState s = cloud(2);
  set_grad(s, 0, 0.001f);
  s.stat[S::kMaxRadius][0] = 50;  // the original goes, the copy has max_radius 0
  Rules r;
  r.max_screen_radius = 20;
  DensifyCounts c;
  const DensifyState out = s4d::ref::densify(s, params(r, 2), UINT32_MAX, 0, &c);
  CHECK(c.cloned == 1);
  CHECK(c.pruned == 1);
  REQUIRE(out.size() == 2);
  check_copy_of(out, 0, s, 0);
  check_moments(out, 0, s, 0, true);  // it is the copy
  // A faint Gaussian's clone is pruned with it.
  s.param[S::kOpacity][0] = -7;
  const DensifyState gone = s4d::ref::densify(s, params(r, 2), UINT32_MAX, 0, &c);
  CHECK(c.pruned == 2);
  CHECK(gone.size() == 1);
}

TEST_CASE("densify twin demotes the growth candidates with the lowest mean gradients to fit the budget") {
  DensifyState s = cloud(6);
  const float grads[6] = {0.0009f, 0.0003f, 0.0001f, 0.0007f, 0.0004f, 0.0005f};  // 2 is below the threshold
  for (size_t i = 0; i < 6; ++i) set_grad(s, i, grads[i]);
  // Gaussian 5 splits (saves 1 when demoted), the rest clone.
  s.param[S::kLogScales][3 * 5] = std::log(0.5f);
  DensifyCounts c;
  // Unlimited: 6 + 5 clones/splits = 11 outputs. Budget 8: demote 1 (0.0003), 4 (0.0004), 5 (0.0005).
  DensifyState out = s4d::ref::densify(s, params({}, 6), 8, 3, &c);
  CHECK(c.demoted == 3);
  CHECK(c.cloned == 2);
  CHECK(c.split == 0);
  CHECK(c.after == 8);
  REQUIRE(out.size() == 8);
  const size_t source[8] = {0, 0, 1, 2, 3, 3, 4, 5};
  for (size_t j = 0; j < 8; ++j) check_copy_of(out, j, s, source[j]);
  // Budget 10: only the lowest (1) goes.
  out = s4d::ref::densify(s, params({}, 6), 10, 3, &c);
  CHECK(c.demoted == 1);
  CHECK(c.after == 10);
  // A budget below the cloud's own size demotes all growth and removes nothing else.
  out = s4d::ref::densify(s, params({}, 6), 2, 3, &c);
  CHECK(c.demoted == 5);
  CHECK(c.after == 6);
}

TEST_CASE("densify twin can prune everything") {
  DensifyState s = cloud(3);
  for (float& l : s.param[S::kOpacity]) l = -8;
  set_grad(s, 0, 0.01f);
  DensifyCounts c;
  const DensifyState out = s4d::ref::densify(s, params({}, 3), UINT32_MAX, 0, &c);
  CHECK(c.after == 0);
  CHECK(c.pruned == 4);  // three originals and one copy
  CHECK(out.size() == 0);
  for (int a = 0; a < S::kAttrs; ++a) CHECK(out.param[a].empty());
}

TEST_CASE("densify twin never grows a Gaussian no view has seen") {
  DensifyState s = cloud(2);
  s.stat[S::kGradCount][0] = 0;
  s.stat[S::kGradAccum][0] = 1;  // stale sum with no count: mean gradient is 0, not inf
  DensifyCounts c;
  s4d::ref::densify(s, params({}, 2), UINT32_MAX, 0, &c);
  CHECK(c.cloned == 0);
  CHECK(c.after == 2);
}

TEST_CASE("opacity reset twin caps opacities and zeroes only the opacity moments") {
  DensifyState s = cloud(3);
  s.param[S::kOpacity] = {-7, 0, 3};
  s4d::ref::densify_reset_opacity(s, 0.01f);
  const float cap = static_cast<float>(std::log(0.01 / 0.99));
  CHECK(s.param[S::kOpacity][0] == -7);
  CHECK(s.param[S::kOpacity][1] == cap);
  CHECK(s.param[S::kOpacity][2] == cap);
  for (float x : s.m[S::kOpacity]) CHECK(x == 0);
  for (float x : s.v[S::kOpacity]) CHECK(x == 0);
  CHECK(s.m[S::kMeans][0] != 0);
}

TEST_CASE("statistics twin: per-view norms versus the batch's norm of the summed gradient") {
  DensifyState s = cloud(2);
  for (auto& st : s.stat) st.assign(2, 0.0f);
  std::vector<float> g1(2 * S4D_G2D_STRIDE, 0), g2(2 * S4D_G2D_STRIDE, 0);
  g1[S4D_G2D_XY] = 0.01f, g1[S4D_G2D_XY + 1] = 0;
  g2[S4D_G2D_XY] = -0.01f, g2[S4D_G2D_XY + 1] = 0.02f;
  const std::vector<uint32_t> r1 = {5, 0}, r2 = {7, 2};
  DensifyState per_view = s;
  s4d::ref::densify_accumulate_view(per_view, g1, r1, 100, 50);
  s4d::ref::densify_accumulate_view(per_view, g2, r2, 100, 50);
  CHECK(per_view.stat[S::kGradAccum][0] == doctest::Approx(0.5 + std::sqrt(0.25 + 0.25)));
  CHECK(per_view.stat[S::kGradCount][0] == 2);
  CHECK(per_view.stat[S::kGradCount][1] == 1);
  CHECK(per_view.stat[S::kMaxRadius][0] == 7);
  std::vector<float> scratch(2 * S4D_ACCUM_SCRATCH_STRIDE, 0);
  s4d::ref::densify_accumulate_batch_add(scratch, g1, r1, 100, 50);
  s4d::ref::densify_accumulate_batch_add(scratch, g2, r2, 100, 50);
  s4d::ref::densify_accumulate_batch_end(s, scratch);
  CHECK(s.stat[S::kGradAccum][0] == doctest::Approx(0.5));  // |(0.5 - 0.5, 0.5)|
  CHECK(s.stat[S::kGradCount][0] == 1);
  CHECK(s.stat[S::kMaxRadius][0] == 7);
  CHECK(s.stat[S::kMaxRadius][1] == 2);
  for (float x : scratch) CHECK(x == 0);
}

TEST_CASE("densify twin can keep the survivors' statistics, new entries starting at zero") {
  DensifyState s = cloud(3);
  s.param[S::kOpacity][0] = -8;  // pruned
  set_grad(s, 2, 0.001f);        // cloned
  DensifyCounts c;
  const DensifyState out = s4d::ref::densify(s, params({}, 3), UINT32_MAX, 0, &c, nullptr, true);
  REQUIRE(out.size() == 3);  // 1, 2, 2's copy
  for (int k = 0; k < S::kStats; ++k) {
    CHECK(out.stat[k][0] == s.stat[k][1]);
    CHECK(out.stat[k][1] == s.stat[k][2]);
    CHECK(out.stat[k][2] == 0.0f);
  }
}
