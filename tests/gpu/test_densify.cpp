// Densification on the GPU (training/trainers/densify, shaders/densify) against its CPU twin on lavapipe:
// densify_classify + densify_map + densify_gather + densify_split on a few thousand random Gaussians
// (every array compared), densify_demote under a budget, empty inputs and results, Adam moment
// semantics, densify_reset_opacity, densify_accumulate (per view and batched) after real
// rasterizer backward passes, and the geometric extremes of docs/kernel-extremes.md.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "s4d/densify/densifier.h"
#include "s4d/engine/buffer_from.h"
#include "s4d/model/trainable_gaussians.h"
#include "s4d/ref/densify_ref.h"
#include "splat_harness.h"
#include "test_context.h"

namespace {

using namespace s4d;
using S = ref::DensifyState;

ref::DensifyState to_ref(const model::HostState& h) {
  ref::DensifyState s;
  s.sh_width = static_cast<uint32_t>(h.cloud.sh_coeffs() * 3);
  s.param = {h.cloud.means, h.cloud.log_scales, h.cloud.quats, h.cloud.opacity_logits, h.cloud.sh};
  for (int a = 0; a < S::kAttrs; ++a) s.m[a] = h.m[splat::kCloudAttrs[a]], s.v[a] = h.v[splat::kCloudAttrs[a]];
  for (int k = 0; k < S::kStats; ++k) s.stat[k] = h.stats[k];
  return s;
}

model::HostState to_host(const ref::DensifyState& s, int sh_degree) {
  model::HostState h;
  h.cloud.sh_degree = sh_degree;
  h.cloud.means = s.param[S::kMeans], h.cloud.log_scales = s.param[S::kLogScales], h.cloud.quats = s.param[S::kQuats];
  h.cloud.opacity_logits = s.param[S::kOpacity], h.cloud.sh = s.param[S::kSh];
  for (int a = 0; a < S::kAttrs; ++a) h.m[splat::kCloudAttrs[a]] = s.m[a], h.v[splat::kCloudAttrs[a]] = s.v[a];
  for (int k = 0; k < S::kStats; ++k) h.stats[k] = s.stat[k];
  return h;
}

// n random Gaussians (SH degree 1) with statistics that send some to each rule under rules() below.
ref::DensifyState random_state(size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1, 1), u01(0, 1);
  ref::DensifyState s;
  s.sh_width = 12;
  s.resize(n);
  for (size_t i = 0; i < n; ++i) {
    const float base = std::log(0.002f) + std::log(30.0f) * u01(rng);  // log-uniform 0.002 .. 0.06
    for (int k = 0; k < 3; ++k) {
      s.param[S::kMeans][3 * i + k] = 2 * u(rng);
      s.param[S::kLogScales][3 * i + k] = base + 0.3f * u(rng);
    }
    for (int k = 0; k < 4; ++k) s.param[S::kQuats][4 * i + k] = u(rng);
    s.param[S::kOpacity][i] = -7 + 11 * u01(rng);
    for (int k = 0; k < 12; ++k) s.param[S::kSh][12 * i + k] = u(rng);
    for (int a = 0; a < S::kAttrs; ++a)
      for (uint32_t e = 0; e < s.width(a); ++e) {
        s.m[a][i * s.width(a) + e] = 0.1f * u(rng);
        s.v[a][i * s.width(a) + e] = 0.01f * (0.1f + u01(rng));
      }
    const float count = static_cast<float>(rng() % 6);  // 0: never seen
    s.stat[S::kGradCount][i] = count;
    s.stat[S::kGradAccum][i] = count * 0.0005f * u01(rng);
    s.stat[S::kMaxRadius][i] = count > 0 ? 30 * u01(rng) : 0;
  }
  return s;
}

densify::DensifyRules rules() {
  densify::DensifyRules r;
  r.dense_scale = 0.01f;
  r.max_screen_radius = 25;
  r.max_world_scale = 0.045f;
  r.seed = 42;
  return r;
}

struct Compared {
  double worst_child_mean = 0;  // largest |GPU - twin| over split children's means
  size_t children = 0;
};

// Every array of the GPU result against the twin: bit-exact except split children's means.
Compared compare(const model::HostState& gpu, const ref::DensifyState& twin, const std::vector<uint32_t>& slots) {
  const ref::DensifyState g = to_ref(gpu);
  REQUIRE(g.size() == twin.size());
  REQUIRE(slots.size() == twin.size());
  Compared c;
  size_t mismatches = 0;
  for (int a = 0; a < S::kAttrs; ++a) {
    const uint32_t w = twin.width(a);
    REQUIRE(g.param[a].size() == twin.param[a].size());
    for (size_t j = 0; j < twin.size(); ++j) {
      const uint32_t kind = slots[j] >> S4D_DENSIFY_SLOT_SHIFT;
      const bool child = kind == S4D_DENSIFY_SLOT_CHILD0 || kind == S4D_DENSIFY_SLOT_CHILD1;
      for (uint32_t e = 0; e < w; ++e) {
        const size_t x = j * w + e;
        if (a == S::kMeans && child) {
          c.worst_child_mean = std::max(c.worst_child_mean, double{std::abs(g.param[a][x] - twin.param[a][x])});
        } else if (ref::float_bits(g.param[a][x]) != ref::float_bits(twin.param[a][x])) {
          if (++mismatches <= 5) FAIL_CHECK(splat::attr_name(splat::kCloudAttrs[a]) << "[" << x << "]: GPU " << g.param[a][x] << " twin " << twin.param[a][x]);
        }
        // Adam moments: bit-exact; zero for copies and children, the source's for originals.
        if (ref::float_bits(g.m[a][x]) != ref::float_bits(twin.m[a][x]) || ref::float_bits(g.v[a][x]) != ref::float_bits(twin.v[a][x]))
          if (++mismatches <= 5) FAIL_CHECK(splat::attr_name(splat::kCloudAttrs[a]) << " moments [" << x << "] differ");
        if (kind != S4D_DENSIFY_SLOT_ORIGINAL && (g.m[a][x] != 0 || g.v[a][x] != 0))
          if (++mismatches <= 5) FAIL_CHECK("new entry " << j << " has non-zero Adam moments");
      }
      if (a == S::kMeans && child) ++c.children;
    }
  }
  for (int k = 0; k < S::kStats; ++k)
    if (g.stat[k] != twin.stat[k] && ++mismatches <= 5) FAIL_CHECK("statistic " << k << " differs from the twin's");
  CHECK(mismatches == 0);
  return c;
}

void check_counts(const densify::DensifyResult& r, const ref::DensifyCounts& c) {
  CHECK(r.before == c.before);
  CHECK(r.cloned == c.cloned);
  CHECK(r.split == c.split);
  CHECK(r.pruned == c.pruned);
  CHECK(r.demoted == c.demoted);
  CHECK(r.after == c.after);
  CHECK(r.after == r.before + r.cloned + r.split - r.pruned);
}

}  // namespace

TEST_CASE("densify_classify, densify_map, densify_gather and densify_split match the twin on random Gaussians") {
  const ref::DensifyState in = random_state(3000, 1);
  model::TrainableGaussians g(test::context(), to_host(in, 1), "cloud");
  densify::Densifier d(test::context());
  const densify::DensifyRules r = rules();
  const densify::DensifyResult res = d.densify(g, r);
  ref::DensifyCounts c;
  std::vector<uint32_t> slots;
  const ref::DensifyState twin = ref::densify(in, densify::classify_params(r, 3000), r.budget, r.seed, &c, &slots);
  check_counts(res, c);
  CHECK(g.size() == res.after);
  // Every rule fired, so each path was exercised.
  CHECK(c.cloned > 50);
  CHECK(c.split > 50);
  CHECK(c.pruned > 50);
  const Compared cmp = compare(g.download(), twin, slots);
  CHECK(cmp.children > 0);
  CHECK(cmp.children <= 2 * c.split);  // children of faint Gaussians are pruned
  // Children's means: the GPU's exp/log/sin/cos against libm in offsets of a few times 0.06, added to
  // means of magnitude up to about 2.2 (one ulp there is 2.4e-7). Measured worst 1.2e-7 on lavapipe
  // (Mesa 22.3.6, LLVM 15); the bound allows 4 ulps for drivers with looser transcendentals.
  CHECK(cmp.worst_child_mean <= 1e-6);
}

TEST_CASE("densify keeps the survivors' statistics when asked to (4DGaussians' separate prune)") {
  const ref::DensifyState in = random_state(1500, 8);
  densify::DensifyRules r = rules();
  r.grow = false;
  r.reset_statistics = false;
  model::TrainableGaussians g(test::context(), to_host(in, 1), "cloud");
  densify::Densifier d(test::context());
  const densify::DensifyResult res = d.densify(g, r);
  ref::DensifyCounts c;
  std::vector<uint32_t> slots;
  const ref::DensifyState twin = ref::densify(in, densify::classify_params(r, 1500), r.budget, r.seed, &c, &slots, true);
  check_counts(res, c);
  CHECK(res.pruned > 0);
  CHECK(res.cloned + res.split == 0);
  compare(g.download(), twin, slots);
  CHECK(std::count_if(twin.stat[S::kGradCount].begin(), twin.stat[S::kGradCount].end(), [](float x) { return x > 0; }) > 500);
}

TEST_CASE("densify_demote keeps the result within the budget by demoting the lowest gradients, like the twin") {
  const ref::DensifyState in = random_state(2500, 2);
  densify::DensifyRules r = rules();
  ref::DensifyCounts unlimited;
  ref::densify(in, densify::classify_params(r, 2500), UINT32_MAX, r.seed, &unlimited);
  REQUIRE(unlimited.cloned + unlimited.split > 200);
  r.budget = unlimited.after - 150;
  model::TrainableGaussians g(test::context(), to_host(in, 1), "cloud");
  densify::Densifier d(test::context());
  const densify::DensifyResult res = d.densify(g, r);
  ref::DensifyCounts c;
  std::vector<uint32_t> slots;
  const ref::DensifyState twin = ref::densify(in, densify::classify_params(r, 2500), r.budget, r.seed, &c, &slots);
  check_counts(res, c);
  CHECK(res.demoted > 0);
  CHECK(res.after <= r.budget);
  CHECK(res.after >= r.budget - 1);  // a demoted split saves up to 2
  compare(g.download(), twin, slots);
}

TEST_CASE("densify handles an empty cloud and a result where everything is pruned") {
  densify::Densifier d(test::context());
  ref::DensifyState empty;
  empty.sh_width = 12;
  empty.resize(0);
  model::TrainableGaussians none(test::context(), to_host(empty, 1), "empty");
  const densify::DensifyResult r0 = d.densify(none, rules());
  CHECK(r0.before == 0);
  CHECK(r0.after == 0);
  CHECK(none.size() == 0);

  ref::DensifyState in = random_state(500, 3);
  for (float& l : in.param[S::kOpacity]) l = -9;
  model::TrainableGaussians g(test::context(), to_host(in, 1), "faint");
  const densify::DensifyResult r = d.densify(g, rules());
  CHECK(r.before == 500);
  CHECK(r.after == 0);
  CHECK(g.size() == 0);
  CHECK(g.download().cloud.opacity_logits.empty());
  // The emptied cloud can be densified again.
  CHECK(d.densify(g, rules()).after == 0);
  densify::DensifyRules bad = rules();
  bad.grad_threshold = -1;
  CHECK_THROWS_AS(d.densify(g, bad), std::invalid_argument);
  bad = rules();
  bad.dense_scale = std::nanf("");
  CHECK_THROWS_AS(d.densify(g, bad), std::invalid_argument);
}

TEST_CASE("densify_split draws the same children for the same seed and different ones for another") {
  const ref::DensifyState in = random_state(800, 6);
  densify::Densifier d(test::context());
  std::vector<float> means[3];
  for (int run = 0; run < 3; ++run) {
    model::TrainableGaussians g(test::context(), to_host(in, 1), "cloud");
    densify::DensifyRules r = rules();
    r.seed = run == 2 ? 43 : 42;
    REQUIRE(d.densify(g, r).split > 0);
    means[run] = g.download().cloud.means;
  }
  CHECK(means[0] == means[1]);
  CHECK(means[0] != means[2]);
}

TEST_CASE("densify keeps the Adam moments of surviving Gaussians and zeroes those of new entries") {
  ref::DensifyState in = random_state(4, 4);
  for (size_t i = 0; i < 4; ++i) {
    in.param[S::kOpacity][i] = 1;
    in.stat[S::kGradCount][i] = 1;
    in.stat[S::kGradAccum][i] = 0;
    in.stat[S::kMaxRadius][i] = 0;
    for (int k = 0; k < 3; ++k) in.param[S::kLogScales][3 * i + k] = std::log(0.005f);
  }
  in.stat[S::kGradAccum][1] = 0.01f;                 // clone
  in.stat[S::kGradAccum][2] = 0.01f;                 // split
  in.param[S::kLogScales][3 * 2 + 1] = std::log(0.03f);
  model::TrainableGaussians g(test::context(), to_host(in, 1), "four");
  densify::Densifier d(test::context());
  const densify::DensifyResult r = d.densify(g, rules());
  CHECK(r.cloned == 1);
  CHECK(r.split == 1);
  REQUIRE(r.after == 6);  // 0, 1, 1's copy, 2's two children, 3
  const model::HostState out = g.download();
  const size_t source[6] = {0, 1, 1, 2, 2, 3};
  const bool fresh[6] = {false, false, true, true, true, false};
  for (size_t j = 0; j < 6; ++j)
    for (splat::Attr a : splat::kCloudAttrs) {
      const uint32_t w = g.width(a);
      for (uint32_t e = 0; e < w; ++e) {
        CHECK(out.m[a][j * w + e] == (fresh[j] ? 0.0f : in.m[splat::index(a)][source[j] * w + e]));
        CHECK(out.v[a][j * w + e] == (fresh[j] ? 0.0f : in.v[splat::index(a)][source[j] * w + e]));
      }
    }
}

TEST_CASE("densify_reset_opacity caps opacities and zeroes the opacity moments like the twin") {
  ref::DensifyState in = random_state(1000, 5);
  model::TrainableGaussians g(test::context(), to_host(in, 1), "cloud");
  densify::Densifier d(test::context());
  d.reset_opacity(g, 0.01f);
  ref::densify_reset_opacity(in, 0.01f);
  const ref::DensifyState out = to_ref(g.download());
  CHECK(out.param == in.param);  // min() of floats: exact
  CHECK(out.m == in.m);          // only the opacity moments are zeroed
  CHECK(out.v == in.v);
  CHECK(std::count_if(out.param[S::kOpacity].begin(), out.param[S::kOpacity].end(),
                      [](float l) { return l < -4.6f; }) > 100);  // some were already below 0.01
  CHECK_THROWS_AS(d.reset_opacity(g, 1.5f), std::invalid_argument);
}

TEST_CASE("densify_accumulate adds per-view and batched statistics like the twin after real backward passes") {
  std::mt19937 rng(7);
  const test::Scene scene = test::random_scene(300, 3, false, rng);
  io::GaussianCloud cloud;
  cloud.sh_degree = 3;
  cloud.means = scene.means, cloud.log_scales = scene.log_scales, cloud.quats = scene.quats;
  cloud.opacity_logits = scene.opacity_logits, cloud.sh = scene.sh;
  // Some Gaussians behind the camera: culled in every view, so their statistics must stay zero.
  for (size_t i = 0; i < 20; ++i) cloud.means[3 * i + 2] = -3;
  model::TrainableGaussians g(test::context(), cloud, "scene");
  splat::Rasterizer raster(test::context());
  densify::Densifier d(test::context());
  engine::Buffer scratch = d.make_batch_scratch(g.size());

  ref::DensifyState twin;
  twin.sh_width = 48;
  twin.resize(g.size());
  std::vector<float> twin_scratch(g.size() * S4D_ACCUM_SCRATCH_STRIDE, 0.0f);
  const uint32_t sizes[2][2] = {{64, 48}, {40, 56}};
  for (const auto& size : sizes) {
    const test::Cam cam = test::random_camera(size[0], size[1], rng);
    raster.forward(g.params(3), test::gpu_camera(cam), {0, 0, 0});
    std::normal_distribution<float> nd(0, 1);
    std::vector<float> v(size_t{size[0]} * size[1] * 3);
    for (float& x : v) x = nd(rng);
    engine::Buffer v_rgb = engine::buffer_from(test::context(), "v_rgb", v);
    raster.backward(g.params(3), {.v_rgb = &v_rgb}, g.grads());
    engine::Recorder rec(test::context(), "accumulate");
    d.record_accumulate(rec, g, raster);
    d.record_accumulate_batch_add(rec, g, raster, scratch);
    test::context().run(std::move(rec));

    const std::vector<float> grad2d = test::context().download<float>(raster.grad2d(), g.size() * S4D_G2D_STRIDE);
    const std::vector<uint32_t> info = test::context().download<uint32_t>(raster.info(), g.size() * 4);
    std::vector<uint32_t> radius(g.size());
    for (size_t i = 0; i < g.size(); ++i) radius[i] = info[4 * i + 2];
    ref::densify_accumulate_view(twin, grad2d, radius, size[0], size[1]);
    ref::densify_accumulate_batch_add(twin_scratch, grad2d, radius, size[0], size[1]);
  }
  auto check_stats = [&](const char* what) {
    CAPTURE(what);
    const model::HostState h = g.download();
    size_t seen = 0;
    for (size_t i = 0; i < g.size(); ++i) {
      // Float sums of the same terms in the same order; length() against sqrt(x^2 + y^2): 1 ulp.
      CHECK(std::abs(h.stats[model::kGradAccum][i] - twin.stat[S::kGradAccum][i]) <= 1e-6f * twin.stat[S::kGradAccum][i]);
      CHECK(h.stats[model::kGradCount][i] == twin.stat[S::kGradCount][i]);
      CHECK(h.stats[model::kMaxRadius][i] == twin.stat[S::kMaxRadius][i]);
      seen += h.stats[model::kGradCount][i] > 0;
    }
    for (size_t i = 0; i < 20; ++i) CHECK(h.stats[model::kGradCount][i] == 0);
    CHECK(seen > 200);
  };
  check_stats("per view");
  {
    engine::Recorder rec(test::context(), "batch end");
    d.record_accumulate_batch_end(rec, g, scratch);
    test::context().run(std::move(rec));
  }
  ref::densify_accumulate_batch_end(twin, twin_scratch);
  check_stats("per view, then one batch of both views");
  for (float x : test::context().download<float>(scratch, g.size() * S4D_ACCUM_SCRATCH_STRIDE)) CHECK(x == 0);
}

TEST_CASE("zero scales, zero and tiny quaternions and nearly singular covariances densify finitely, like the twin") {
  ref::DensifyState in = random_state(300, 12);
  const float split = std::log(0.03f);  // above dense_scale (0.01), below max_world_scale (0.045): split
  auto set = [&](size_t i, std::array<float, 3> ls, std::array<float, 4> q) {
    for (int k = 0; k < 3; ++k) in.param[S::kLogScales][3 * i + k] = ls[k];
    for (int k = 0; k < 4; ++k) in.param[S::kQuats][4 * i + k] = q[k];
    in.param[S::kOpacity][i] = 2;
    in.stat[S::kGradCount][i] = 3, in.stat[S::kGradAccum][i] = 0.03f, in.stat[S::kMaxRadius][i] = 5;
  };
  for (size_t i = 0; i < 5; ++i) {
    set(i, {split, split, split}, {0, 0, 0, 0});                      // zero quaternion: identity rotation
    set(5 + i, {split, split, split}, {1e-20f, 2e-20f, 3e-20f, 4e-20f});  // |q|^2 of 3e-39 is a denormal
    set(10 + i, {-100, -100, -100}, {1, 0, 0, 0});                  // exp(-100) is 0 in float: zero scales, cloned
    set(15 + i, {split, split, std::log(1e-9f)}, {0.9f, 0.3f, 0.2f, 0.1f});  // nearly singular, tilted
  }
  model::TrainableGaussians g(test::context(), to_host(in, 1), "cloud");
  densify::Densifier d(test::context());
  const densify::DensifyRules r = rules();
  const densify::DensifyResult res = d.densify(g, r);
  ref::DensifyCounts c;
  std::vector<uint32_t> slots;
  const ref::DensifyState twin = ref::densify(in, densify::classify_params(r, 300), r.budget, r.seed, &c, &slots);
  check_counts(res, c);
  for (int a = 0; a < S::kAttrs; ++a)
    for (const float x : twin.param[a]) REQUIRE(std::isfinite(x));
  // As the random test: children's means within 1e-6 (exp, log, sin, cos on GPU and in libm).
  const Compared cmp = compare(g.download(), twin, slots);
  CHECK(cmp.children >= 30);  // the 15 split Gaussians above, two children each
  CHECK(cmp.worst_child_mean <= 1e-6);
}
