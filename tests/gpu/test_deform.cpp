// The deformation field kernels (deform_feat, deform_fwd, deform_bwd, deform_feat_bwd + deform_wgrad
// and their _cas variants, deform_reg) against the double CPU twin on lavapipe: a small random field
// (8^3 x 6 base planes, 2 levels, C = 4, W = 16, one extra trunk layer, all five heads), and
// 4DGaussians' DyNeRF MLP (C = 16, W = 128, five heads), with 300 Gaussians, some outside the AABB
// (border clamp) and some still. Still Gaussians are drawn anywhere and then put last (deform::split_by_motion, as the
// trainer does), so the field's moving prefix + copied tail is checked against the twin's
// per-Gaussian masked rule. Each twin is fed the exact float values (and order) the GPU holds.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "s4d/deform/deformation_field.h"
#include "s4d/deform/deformed_cloud.h"
#include "s4d/deform/motion_split.h"
#include "expect_allclose.h"
#include "s4d/engine/buffer_from.h"
#include "s4d/io/half_float.h"
#include "s4d/ref/deform_ref.h"
#include "s4d/ref/hexplane_reg_ref.h"
#include "s4d/ref/random_deform.h"
#include "s4d/scene/deformed_scene.h"
#include "test_context.h"

namespace {

using namespace s4d;

constexpr uint32_t kN = 300;  // five workgroups of 64, the last one partial
constexpr float kTime = 0.37f;

using ref::uniform;

std::vector<double> to_double(const std::vector<float>& v) { return {v.begin(), v.end()}; }

deform::FieldConfig test_config() {
  deform::FieldConfig c;
  c.resolution = {8, 8, 8, 6};
  c.multires = {1, 2};
  c.channels = 4;
  c.width = 16;
  c.trunk_extra = 1;
  c.heads = S4D_DEFORM_HEADS_DYNERF;
  c.aabb_min = {-1.0f, -2.0f, 0.5f};
  c.aabb_max = {1.5f, 1.0f, 2.5f};
  return c;
}

// Host copies of the Gaussians (still ones last, host.still_mask marks them) and their device buffers.
struct Scene {
  ref::DeformGaussians<float> host;
  uint32_t still_count = 0;
  std::vector<uint32_t> order;  // Gaussian order[j] as drawn is at j
  engine::Buffer means, log_scales, quats, opacity, sh;
  deform::CanonicalGaussians canonical() const {
    return {{{&means, &log_scales, &quats, &opacity, &sh}}, kN, still_count, S4D_DEFORM_SH_COEFFS};
  }
};

// The Gaussians in the split's order: every array's rows and the mask move together.
ref::DeformGaussians<float> reorder(const ref::DeformGaussians<float>& g, const deform::MotionSplit& split) {
  auto rows = [&](const std::vector<float>& v) { return deform::gather_rows<float>(v, split.order, v.size() / kN); };
  return {rows(g.means), rows(g.log_scales), rows(g.quats), rows(g.opacity_logits), rows(g.sh),
          deform::gather_rows<uint32_t>(g.still_mask, split.order, 1)};
}

Scene make_scene(const deform::FieldConfig& c, unsigned seed, uint32_t still_every) {
  std::mt19937 rng(seed);
  Scene s;
  // every tenth Gaussian outside the AABB
  s.host = ref::random_gaussians<float>(c.aabb_min, c.aabb_max, kN, rng,
                                        {.outside_every = 10, .sh_coeffs = S4D_DEFORM_SH_COEFFS});
  for (uint32_t i = 0; i < kN; ++i) s.host.still_mask.push_back(still_every != 0 && i % still_every == 0 ? 1u : 0u);
  const deform::MotionSplit split = deform::split_by_motion(s.host.still_mask);
  s.host = reorder(s.host, split);
  s.still_count = split.still_count;
  s.order = split.order;
  engine::Context& ctx = test::context();
  s.means = engine::buffer_from(ctx, "means", s.host.means);
  s.log_scales = engine::buffer_from(ctx, "log_scales", s.host.log_scales);
  s.quats = engine::buffer_from(ctx, "quats", s.host.quats);
  s.opacity = engine::buffer_from(ctx, "opacity_logits", s.host.opacity_logits);
  s.sh = engine::buffer_from(ctx, "sh", s.host.sh);
  return s;
}

// A field on the GPU with planes around 1 (so the 6-fold products stay O(1)) and its double twin.
struct Field {
  deform::DeformationField gpu;
  ref::DeformField<double> twin;
};

Field make_field(const deform::FieldConfig& c, unsigned seed, deform::DeformOptions options = {}) {
  Field f{deform::DeformationField(test::context(), c, seed, "test field", options), {}};
  std::mt19937 rng(seed);
  f.gpu.upload_planes(uniform(f.gpu.plane_floats(), rng, 0.6f, 1.4f));
  f.twin.shape = f.gpu.shape();
  const std::array<float, 3> scale = deform::aabb_scale(c);
  for (int k = 0; k < 3; ++k) f.twin.aabb_max[k] = c.aabb_max[k], f.twin.aabb_scale[k] = scale[k];
  f.twin.planes = to_double(f.gpu.download_planes());
  f.twin.mlp = to_double(f.gpu.download_mlp());
  return f;
}

ref::DeformGaussians<double> to_double(const ref::DeformGaussians<float>& g) {
  return {to_double(g.means), to_double(g.log_scales), to_double(g.quats), to_double(g.opacity_logits),
          to_double(g.sh), g.still_mask};
}

struct Deformed {
  engine::Buffer means, log_scales, quats, opacity, sh;
  splat::GaussianBuffers<engine::Buffer> view() { return {{&means, &log_scales, &quats, &opacity, &sh}}; }
};

Deformed run_forward(const Field& f, const Scene& s, float time = kTime) {
  engine::Context& ctx = test::context();
  Deformed d{engine::Buffer(ctx, "out means", kN * 12), engine::Buffer(ctx, "out log_scales", kN * 12),
             engine::Buffer(ctx, "out quats", kN * 16), engine::Buffer(ctx, "out opacity", kN * 4),
             engine::Buffer(ctx, "out sh", kN * 3 * S4D_DEFORM_SH_COEFFS * 4)};
  engine::Recorder rec(ctx, "deform forward");
  f.gpu.record_forward(rec, s.canonical(), time, d.view());
  ctx.run(std::move(rec));
  return d;
}

// Random cotangents of the deformed parameters, on the host and the device.
struct Cotangents {
  ref::DeformGaussians<float> host;
  engine::Buffer v_means, v_log_scales, v_quats, v_opacity, v_sh;
  splat::GaussianGrads view() { return {{&v_means, &v_log_scales, &v_quats, &v_opacity, &v_sh}}; }
};

Cotangents make_cotangents(unsigned seed) {
  std::mt19937 rng(seed);
  Cotangents v;
  v.host.means = uniform(3 * kN, rng, -1, 1);
  v.host.log_scales = uniform(3 * kN, rng, -1, 1);
  v.host.quats = uniform(4 * kN, rng, -1, 1);
  v.host.opacity_logits = uniform(kN, rng, -1, 1);
  v.host.sh = uniform(kN * 3 * S4D_DEFORM_SH_COEFFS, rng, -1, 1);
  engine::Context& ctx = test::context();
  v.v_means = engine::buffer_from(ctx, "v_means", v.host.means);
  v.v_log_scales = engine::buffer_from(ctx, "v_log_scales", v.host.log_scales);
  v.v_quats = engine::buffer_from(ctx, "v_quats", v.host.quats);
  v.v_opacity = engine::buffer_from(ctx, "v_opacity_logits", v.host.opacity_logits);
  v.v_sh = engine::buffer_from(ctx, "v_sh", v.host.sh);
  return v;
}

void run_backward(Field& f, const Scene& s, Cotangents& v, float time = kTime) {
  engine::Context& ctx = test::context();
  engine::Recorder rec(ctx, "deform backward");
  f.gpu.record_zero_grads(rec);
  rec.barrier();
  f.gpu.record_backward(rec, s.canonical(), time, v.view());
  ctx.run(std::move(rec));
}

// 4DGaussians' DyNeRF MLP (the default and quality presets' width and heads) on test_config()'s planes.
deform::FieldConfig paper_config() {
  deform::FieldConfig c = test_config();
  c.channels = 16;
  c.width = 128;
  c.trunk_extra = 0;
  return c;
}

// The GPU backward of config c against the twin: v_means (in place), v_planes, v_mlp. Float
// accumulation over 300 Gaussians in atomic order against double (deform_wgrad: row order within its
// 256-row spans, so the default single pass also covers a span boundary). Measured worst on lavapipe
// (Mesa 22.3.6), relative to the largest entry, still Gaussians last: test_config() v_means 4.1e-7,
// v_planes 7.5e-7, v_mlp 5.0e-7 (float atomics, CAS and 100-row passes alike, the same with the
// per-layer kernels); paper_config() 1.1e-6, 5.2e-7, 8.0e-7. 1e-5 leaves room for other summation orders.
void check_backward(const deform::FieldConfig& c, deform::DeformOptions options) {
  Field f = make_field(c, 21, options);
  Scene s = make_scene(c, 22, 7);
  Cotangents v = make_cotangents(23);
  run_backward(f, s, v);
  const ref::DeformGrads<double> r = ref::deform_backward(f.twin, to_double(s.host), double(kTime), to_double(v.host));
  engine::Context& ctx = test::context();
  const std::vector<float> v_means = ctx.download<float>(v.v_means, 3 * kN);
  REQUIRE(s.still_count == 43);  // i % 7 == 0 of 300, now the last 43
  for (uint32_t k = 3 * (kN - s.still_count); k < 3 * kN; ++k)  // still: cotangents pass through, bit for bit
    REQUIRE(v_means[k] == v.host.means[k]);
  test::expect_allclose(v_means, r.v.means, {.of_largest = 1e-5}, "v_means");
  test::expect_allclose(ctx.download<float>(f.gpu.v_planes(), f.gpu.plane_floats()), r.v_planes, {.of_largest = 1e-5}, "v_planes");
  test::expect_allclose(ctx.download<float>(f.gpu.v_mlp(), f.gpu.mlp_floats()), r.v_mlp, {.of_largest = 1e-5}, "v_mlp");
}

}  // namespace

TEST_CASE("deform_fwd matches the twin: every head's output, still Gaussians copied unchanged") {
  const deform::FieldConfig c = test_config();
  Field f = make_field(c, 1);
  Scene s = make_scene(c, 2, 5);
  Deformed d = run_forward(f, s);
  const ref::DeformGaussians<double> r = ref::deform_forward(f.twin, to_double(s.host), double(kTime));
  engine::Context& ctx = test::context();
  const std::vector<float> means = ctx.download<float>(d.means, 3 * kN), sh = ctx.download<float>(d.sh, 48 * kN);
  // Float features and a 4-layer float MLP against double. Measured worst on lavapipe (Mesa 22.3.6),
  // relative to the largest output: means 1.1e-7, log_scales 1.5e-7, quats 2.5e-7, opacity 1.0e-7, sh 4.1e-7.
  test::expect_allclose(means, r.means, {.of_largest = 2e-6}, "means");
  test::expect_allclose(ctx.download<float>(d.log_scales, 3 * kN), r.log_scales, {.of_largest = 2e-6}, "d.log_scales");
  test::expect_allclose(ctx.download<float>(d.quats, 4 * kN), r.quats, {.of_largest = 2e-6}, "d.quats");
  test::expect_allclose(ctx.download<float>(d.opacity, kN), r.opacity_logits, {.of_largest = 2e-6}, "d.opacity");
  test::expect_allclose(sh, r.sh, {.of_largest = 2e-6}, "sh");
  REQUIRE(s.still_count == 60);  // i % 5 == 0 of 300, now the last 60; 240 moving (a partial workgroup)
  for (uint32_t i = kN - s.still_count; i < kN; ++i) {  // still: bit-for-bit copies
    for (int k = 0; k < 3; ++k) REQUIRE(means[3 * i + k] == s.host.means[3 * i + k]);
    for (int k = 0; k < 48; ++k) REQUIRE(sh[48 * i + k] == s.host.sh[48 * i + k]);
  }
  // Moving Gaussians do move, up to the last one of the prefix.
  CHECK(std::abs(means[0] - s.host.means[0]) > 1e-4);
  CHECK(std::abs(means[3 * 239] - s.host.means[3 * 239]) > 1e-4);
}

TEST_CASE("a field over the times [0, 1] gives at time t the twin's output at grid time 2t - 1") {
  deform::FieldConfig c = test_config();
  c.time_range = {0, 1};
  Field f = make_field(c, 3);
  Scene s = make_scene(c, 4, 0);
  for (const float time : {0.0f, 0.3f, 1.0f}) {
    CAPTURE(time);
    Deformed d = run_forward(f, s, time);
    const ref::DeformGaussians<double> r = ref::deform_forward(f.twin, to_double(s.host), 2.0 * time - 1.0);
    // Float against double, as the first case. Measured worst on lavapipe: 1.6e-7 of the largest.
    test::expect_allclose(test::context().download<float>(d.means, 3 * kN), r.means, {.of_largest = 2e-6}, "means");
  }
}

TEST_CASE("the moving prefix gives every moving Gaussian the bits of a run with nothing still (fwd, v_means)") {
  const deform::FieldConfig c = test_config();
  Field f = make_field(c, 7);
  Scene all = make_scene(c, 8, 0), split = make_scene(c, 8, 4);  // the same Gaussians; every fourth still
  const std::vector<uint32_t>& order = split.order;
  Deformed a = run_forward(f, all), b = run_forward(f, split);
  Cotangents va = make_cotangents(9), vb = make_cotangents(9);
  engine::Context& ctx = test::context();
  // The split scene's cotangents in its order, so Gaussian order[j] has the same ones in both runs.
  for (auto [host, buffer] : {std::pair{&vb.host.means, &vb.v_means}, {&vb.host.log_scales, &vb.v_log_scales},
                              {&vb.host.quats, &vb.v_quats}, {&vb.host.opacity_logits, &vb.v_opacity}, {&vb.host.sh, &vb.v_sh}}) {
    *host = deform::gather_rows<float>(*host, order, host->size() / kN);
    ctx.upload(*buffer, std::span<const float>(*host));
  }
  run_backward(f, all, va);
  run_backward(f, split, vb);
  const std::vector<float> means_a = ctx.download<float>(a.means, 3 * kN), means_b = ctx.download<float>(b.means, 3 * kN);
  const std::vector<float> sh_a = ctx.download<float>(a.sh, 48 * kN), sh_b = ctx.download<float>(b.sh, 48 * kN);
  const std::vector<float> v_a = ctx.download<float>(va.v_means, 3 * kN), v_b = ctx.download<float>(vb.v_means, 3 * kN);
  for (uint32_t j = 0; j < kN - split.still_count; ++j) {  // per-Gaussian work: no reordering of sums
    const uint32_t i = order[j];
    for (int k = 0; k < 3; ++k) REQUIRE(means_b[3 * j + k] == means_a[3 * i + k]);
    for (int k = 0; k < 48; ++k) REQUIRE(sh_b[48 * j + k] == sh_a[48 * i + k]);
    for (int k = 0; k < 3; ++k) REQUIRE(v_b[3 * j + k] == v_a[3 * i + k]);
  }
}

TEST_CASE("deform_fwd is deterministic: a rerun gives identical bits") {
  const deform::FieldConfig c = test_config();
  Field f = make_field(c, 3);
  Scene s = make_scene(c, 4, 0);
  Deformed a = run_forward(f, s), b = run_forward(f, s);
  engine::Context& ctx = test::context();
  CHECK(ctx.download<float>(a.means, 3 * kN) == ctx.download<float>(b.means, 3 * kN));
  CHECK(ctx.download<float>(a.quats, 4 * kN) == ctx.download<float>(b.quats, 4 * kN));
  CHECK(ctx.download<float>(a.sh, 48 * kN) == ctx.download<float>(b.sh, 48 * kN));
}

TEST_CASE("deform_fwd with the D-NeRF heads writes only means, log_scales and quats") {
  deform::FieldConfig c = test_config();
  c.heads = S4D_DEFORM_HEADS_DNERF;
  c.trunk_extra = 0;
  Field f = make_field(c, 5);
  Scene s = make_scene(c, 6, 0);
  engine::Context& ctx = test::context();
  engine::Buffer means(ctx, "out means", kN * 12), scales(ctx, "out log_scales", kN * 12), quats(ctx, "out quats", kN * 16);
  engine::Recorder rec(ctx, "deform forward dnerf");
  f.gpu.record_forward(rec, s.canonical(), kTime, {&means, &scales, &quats, nullptr, nullptr});
  ctx.run(std::move(rec));
  const ref::DeformGaussians<double> r = ref::deform_forward(f.twin, to_double(s.host), double(kTime));
  test::expect_allclose(ctx.download<float>(means, 3 * kN), r.means, {.of_largest = 2e-6}, "means");  // measured 2.2e-7 (quats 3.5e-7)
  test::expect_allclose(ctx.download<float>(quats, 4 * kN), r.quats, {.of_largest = 2e-6}, "quats");
  CHECK(ctx.download<float>(s.opacity, kN) == s.host.opacity_logits);  // the canonical input is untouched
}

TEST_CASE("deform-to-time (DeformedCloud): the heads that are on come from the field, the others stay canonical") {
  deform::FieldConfig c = test_config();
  c.heads = S4D_DEFORM_HEADS_DNERF;
  Field f = make_field(c, 7);
  Scene s = make_scene(c, 8, 4);  // every fourth Gaussian still: the field's copied tail
  const splat::GaussianParams canonical{.buffers = {{&s.means, &s.log_scales, &s.quats, &s.opacity, &s.sh}},
                                        .count = kN, .sh_degree = 3, .sh_coeffs = S4D_DEFORM_SH_COEFFS};
  engine::Context& ctx = test::context();
  deform::DeformedCloud cloud(ctx, c.heads, kN, S4D_DEFORM_SH_COEFFS);
  CHECK(cloud.outputs()[splat::Attr::opacity_logits] == nullptr);  // allocated for the heads that are on only
  CHECK(cloud.outputs()[splat::Attr::sh] == nullptr);
  engine::Recorder rec(ctx, "deform to time");
  const splat::GaussianParams p = cloud.record(rec, f.gpu, canonical, s.still_count, kTime);
  ctx.run(std::move(rec));
  CHECK(p[splat::Attr::opacity_logits] == &s.opacity);
  CHECK(p[splat::Attr::sh] == &s.sh);
  CHECK(p.sh_degree == 3);
  REQUIRE(p[splat::Attr::quats] == cloud.outputs()[splat::Attr::quats]);
  engine::Buffer means(ctx, "out means", kN * 12), scales(ctx, "out log_scales", kN * 12), quats(ctx, "out quats", kN * 16);
  engine::Recorder direct(ctx, "deform forward");
  f.gpu.record_forward(direct, s.canonical(), kTime, {{&means, &scales, &quats}});
  ctx.run(std::move(direct));
  CHECK(ctx.download<float>(*p[splat::Attr::means], 3 * kN) == ctx.download<float>(means, 3 * kN));  // the same kernels: bit for bit
  CHECK(ctx.download<float>(*p[splat::Attr::log_scales], 3 * kN) == ctx.download<float>(scales, 3 * kN));
  CHECK(ctx.download<float>(*p[splat::Attr::quats], 4 * kN) == ctx.download<float>(quats, 4 * kN));

  deform::DeformedCloud fewer(ctx, c.heads, kN - 1, S4D_DEFORM_SH_COEFFS);
  deform::DeformedCloud all_heads(ctx, S4D_DEFORM_HEADS_DYNERF, kN, S4D_DEFORM_SH_COEFFS);
  engine::Recorder refused(ctx, "refused");  // after the clouds: destroyed before them, never submitted
  CHECK_THROWS_WITH_AS(fewer.record(refused, f.gpu, canonical, 0, kTime),
                       "deformed cloud: sized for 299 Gaussians with 16 SH coefficients, given 300 with 16",
                       std::invalid_argument);
  CHECK_THROWS_WITH_AS(all_heads.record(refused, f.gpu, canonical, 0, kTime),
                       "deformed cloud: the field's heads 7 differ from the cloud's 31", std::invalid_argument);
  CHECK_THROWS_AS(deform::DeformedCloud().record(refused, f.gpu, canonical, 0, kTime), std::invalid_argument);
}

TEST_CASE("the backward kernels match the twin: canonical means, planes, MLP weights and biases") {
  check_backward(test_config(), {});
}

TEST_CASE("deform_feat_bwd_cas + deform_wgrad_cas (compare-and-swap adds) match the twin") {
  check_backward(test_config(), {.force_cas_atomics = true});
}

TEST_CASE("the backward in several scratch passes (100, 100, 100 Gaussians) matches the twin") {
  check_backward(test_config(), {.scratch_rows = 100});
}

TEST_CASE("still Gaussians give the field no gradient and keep their cotangents (deform_bwd, deform_wgrad)") {
  const deform::FieldConfig c = test_config();
  Field f = make_field(c, 31);
  Scene s = make_scene(c, 32, 1);  // every Gaussian still
  Cotangents v = make_cotangents(33);
  run_backward(f, s, v);
  engine::Context& ctx = test::context();
  const std::vector<float> v_planes = ctx.download<float>(f.gpu.v_planes(), f.gpu.plane_floats());
  const std::vector<float> v_mlp = ctx.download<float>(f.gpu.v_mlp(), f.gpu.mlp_floats());
  CHECK(std::all_of(v_planes.begin(), v_planes.end(), [](float x) { return x == 0.0f; }));
  CHECK(std::all_of(v_mlp.begin(), v_mlp.end(), [](float x) { return x == 0.0f; }));
  CHECK(ctx.download<float>(v.v_means, 3 * kN) == v.host.means);
}

TEST_CASE("rendering a run whose checkpoint marks still Gaussians anywhere (before the split) keeps them canonical") {
  const deform::FieldConfig c = test_config();
  Field f = make_field(c, 35);
  const Scene s = make_scene(c, 36, 0);
  io::GaussianCloud cloud;
  cloud.means = s.host.means, cloud.log_scales = s.host.log_scales, cloud.quats = s.host.quats;
  cloud.opacity_logits = s.host.opacity_logits, cloud.sh = s.host.sh, cloud.sh_degree = 3;
  std::vector<uint32_t> mask(kN, 0);
  for (uint32_t i = 0; i < kN; i += 3) mask[i] = mask[i + 1] = 1;  // runs of two still Gaussians
  const std::vector<float> planes = f.gpu.download_planes(), mlp = f.gpu.download_mlp();
  engine::Context& ctx = test::context();
  scene::DeformedScene all(ctx, cloud, c, planes, mlp, {}, 3), old(ctx, cloud, c, planes, mlp, mask, 3);
  const std::vector<float> means_all = ctx.download<float>(*all.at(kTime, {})[splat::Attr::means], 3 * kN);
  const splat::GaussianParams p = old.at(kTime, {});
  const std::vector<float> means = ctx.download<float>(*p[splat::Attr::means], 3 * kN), sh = ctx.download<float>(*p[splat::Attr::sh], 48 * kN);
  for (uint32_t i = 0; i < kN; ++i) {  // the checkpoint's order, every value bit for bit
    const std::vector<float>& want = mask[i] ? s.host.means : means_all;
    for (int k = 0; k < 3; ++k) REQUIRE(means[3 * i + k] == want[3 * i + k]);
    if (mask[i])
      for (int k = 0; k < 48; ++k) REQUIRE(sh[48 * i + k] == s.host.sh[48 * i + k]);
  }
}

TEST_CASE("a deformed scene asked the same time again returns the same Gaussians; a new time runs the field") {
  const deform::FieldConfig c = test_config();
  Field f = make_field(c, 37);
  const Scene s = make_scene(c, 38, 0);
  io::GaussianCloud cloud;
  cloud.means = s.host.means, cloud.log_scales = s.host.log_scales, cloud.quats = s.host.quats;
  cloud.opacity_logits = s.host.opacity_logits, cloud.sh = s.host.sh, cloud.sh_degree = 3;
  engine::Context& ctx = test::context();
  scene::DeformedScene scene(ctx, cloud, c, f.gpu.download_planes(), f.gpu.download_mlp(), {}, 3);
  auto means_at = [&](double t) { return ctx.download<float>(*scene.at(t, {})[splat::Attr::means], 3 * kN); };
  const std::vector<float> first = means_at(0.25), again = means_at(0.25), other = means_at(0.75), back = means_at(0.25);
  CHECK(again == first);
  CHECK(other != first);
  CHECK(back == first);  // the field's forward is deterministic: the same values bit for bit
}

TEST_CASE("a deformed scene with its canonical SH as halves is, bit for bit, the float scene of the rounded SH") {
  const deform::FieldConfig c = test_config();  // every head, the sh head included
  Field f = make_field(c, 39);
  const Scene s = make_scene(c, 40, 0);
  io::GaussianCloud cloud;
  cloud.means = s.host.means, cloud.log_scales = s.host.log_scales, cloud.quats = s.host.quats;
  cloud.opacity_logits = s.host.opacity_logits, cloud.sh = s.host.sh, cloud.sh_degree = 3;
  io::GaussianCloud rounded = cloud;
  for (float& v : rounded.sh) v = io::half_to_float(io::float_to_half(v));
  REQUIRE(rounded.sh != cloud.sh);
  const std::vector<float> planes = f.gpu.download_planes(), mlp = f.gpu.download_mlp();
  engine::Context& ctx = test::context();
  scene::DeformedScene half(ctx, cloud, c, planes, mlp, {}, 3, splat::Storage::f16),
      single(ctx, rounded, c, planes, mlp, {}, 3);
  // deform_fwd_half reads each half's exact value, so it computes what deform_fwd does on them.
  const splat::GaussianParams p = half.at(kTime, {}), q = single.at(kTime, {});
  CHECK(p.sh_storage == splat::Storage::f32);  // the deformed SH the rasterizer reads are float
  const std::vector<float> sh = ctx.download<float>(*p[splat::Attr::sh], 48 * kN);
  CHECK(sh == ctx.download<float>(*q[splat::Attr::sh], 48 * kN));
  CHECK(ctx.download<float>(*p[splat::Attr::means], 3 * kN) == ctx.download<float>(*q[splat::Attr::means], 3 * kN));
  CHECK(std::abs(sh[0] - rounded.sh[0]) > 1e-4);  // the field does move SH
  CHECK(half.sh_style_bytes() + 48 * kN * 2 == single.sh_style_bytes());  // the canonical SH in half the bytes

  // Still Gaussians anywhere (an old checkpoint's mask) get their canonical SH copied, so those stay float.
  std::vector<uint32_t> mask(kN, 0);
  for (uint32_t i = 0; i < kN; i += 3) mask[i] = 1;
  scene::DeformedScene old_half(ctx, cloud, c, planes, mlp, mask, 3, splat::Storage::f16),
      old_single(ctx, cloud, c, planes, mlp, mask, 3);
  CHECK(old_half.sh_style_bytes() == old_single.sh_style_bytes());
  CHECK(ctx.download<float>(*old_half.at(kTime, {})[splat::Attr::sh], 48 * kN) ==
        ctx.download<float>(*old_single.at(kTime, {})[splat::Attr::sh], 48 * kN));
}

TEST_CASE("deform_reg matches the twin: regulariser value and accumulated plane gradient") {
  const deform::FieldConfig c = test_config();
  Field f = make_field(c, 41);
  engine::Context& ctx = test::context();
  std::mt19937 rng(42);
  const std::vector<float> existing = uniform(f.gpu.plane_floats(), rng, -1, 1);
  ctx.upload(f.gpu.v_planes(), std::span<const float>(existing));
  const deform::RegulariserWeights w{.plane_tv = 2e-4f, .time_smoothness = 1e-3f, .l1_time_planes = 1e-4f};
  engine::Recorder rec(ctx, "deform regularisers");
  f.gpu.record_regularisers(rec, w);
  ctx.run(std::move(rec));
  std::vector<double> grad = to_double(existing);
  const double value = ref::hexplane_regularisers(
      f.twin.shape, f.twin.planes, {.plane_tv = w.plane_tv, .time_smoothness = w.time_smoothness, .l1_time = w.l1_time_planes},
      &grad);
  // Float workgroup sums of ~10^4 terms, summed in double: measured 3.6e-9 relative.
  CHECK(f.gpu.regulariser_value() == doctest::Approx(value).epsilon(1e-6));
  // Gradients of O(1e-4) added to O(1) values: measured 3.0e-8 relative to the largest entry.
  test::expect_allclose(ctx.download<float>(f.gpu.v_planes(), f.gpu.plane_floats()), grad, {.of_largest = 1e-6}, "f.gpu.v_planes()");
}

TEST_CASE("deformation field errors name the field and the buffer") {
  const deform::FieldConfig c = test_config();
  Field f = make_field(c, 51);
  Scene s = make_scene(c, 52, 0);
  engine::Context& ctx = test::context();
  engine::Buffer small(ctx, "small", 16);
  Deformed d = run_forward(f, s);
  engine::Recorder rec(ctx, "errors");
  deform::CanonicalGaussians g = s.canonical();
  g.sh_coeffs = 9;
  CHECK_THROWS_WITH_AS(f.gpu.record_forward(rec, g, kTime, d.view()), "test field: the sh head needs sh_coeffs = 16, got 9",
                       std::invalid_argument);
  splat::GaussianBuffers<engine::Buffer> out = d.view();
  out[splat::Attr::quats] = &small;
  CHECK_THROWS_WITH_AS(f.gpu.record_forward(rec, s.canonical(), kTime, out),
                       "test field: buffer 'deformed quats' (small) holds 16 bytes, needs 4800", std::invalid_argument);
  CHECK_THROWS_AS(f.gpu.upload_mlp(std::vector<float>(3)), std::invalid_argument);
  g = s.canonical();
  g.sh_storage = splat::Storage::f16;  // halves are read by the forward only
  Cotangents v = make_cotangents(53);
  CHECK_THROWS_WITH_AS(f.gpu.record_backward(rec, g, kTime, v.view()),
                       "test field: the backward needs float SH; halves are a trained model's render-side storage",
                       std::invalid_argument);
}

TEST_CASE("4DGaussians' width-128, five-head MLP runs on every device and matches the twin, forward and backward") {
  // Before the per-layer kernels, lavapipe refused it: one invocation ran the whole MLP, past
  // llvmpipe's 65535 loop iterations.
  const deform::FieldConfig c = paper_config();
  Field f = make_field(c, 61);
  REQUIRE(f.gpu.mlp_floats() == 94395);  // 4DGaussians' DyNeRF decoder with C = 16, 2 levels
  Scene s = make_scene(c, 62, 5);
  Deformed d = run_forward(f, s);
  const ref::DeformGaussians<double> r = ref::deform_forward(f.twin, to_double(s.host), double(kTime));
  engine::Context& ctx = test::context();
  // Float sums of 32 and 128 terms against double. Measured worst on lavapipe (Mesa 22.3.6), relative
  // to the largest output: means 2.0e-7, log_scales 1.8e-7, quats 3.4e-7, opacity 1.8e-7, sh 4.2e-7.
  test::expect_allclose(ctx.download<float>(d.means, 3 * kN), r.means, {.of_largest = 2e-6}, "d.means");
  test::expect_allclose(ctx.download<float>(d.log_scales, 3 * kN), r.log_scales, {.of_largest = 2e-6}, "d.log_scales");
  test::expect_allclose(ctx.download<float>(d.quats, 4 * kN), r.quats, {.of_largest = 2e-6}, "d.quats");
  test::expect_allclose(ctx.download<float>(d.opacity, kN), r.opacity_logits, {.of_largest = 2e-6}, "d.opacity");
  test::expect_allclose(ctx.download<float>(d.sh, 48 * kN), r.sh, {.of_largest = 2e-6}, "d.sh");
  // Sums over 300 Gaussians and five heads, in atomic order: see check_backward.
  check_backward(c, {});
}

TEST_CASE("deform_fwd in several scratch passes (100, 100, 100 Gaussians) gives the bits of one pass") {
  const deform::FieldConfig c = test_config();
  Field one = make_field(c, 71), three = make_field(c, 71, {.scratch_rows = 100});
  Scene s = make_scene(c, 72, 0);
  Deformed a = run_forward(one, s), b = run_forward(three, s);
  engine::Context& ctx = test::context();
  CHECK(ctx.download<float>(a.means, 3 * kN) == ctx.download<float>(b.means, 3 * kN));
  CHECK(ctx.download<float>(a.sh, 48 * kN) == ctx.download<float>(b.sh, 48 * kN));
  CHECK(std::abs(ctx.download<float>(b.means, 3 * kN)[3 * 250] - s.host.means[3 * 250]) > 1e-4);  // the third pass ran
}

TEST_CASE("times far outside [0, 1] and Gaussians 1000x outside the field's box deform finitely, like the twin") {
  const deform::FieldConfig c = test_config();
  for (const float time : {-3.0f, 7.5f}) {
    CAPTURE(time);
    Field f = make_field(c, 31);
    Scene s = make_scene(c, 32, 0);
    for (float& m : s.host.means) m *= 1000.0f;  // the box spans ~3 units: these sit thousands away
    s.means = engine::buffer_from(test::context(), "means", s.host.means);
    Deformed d = run_forward(f, s, time);
    const ref::DeformGaussians<double> r = ref::deform_forward(f.twin, to_double(s.host), double(time));
    engine::Context& ctx = test::context();
    // Both clamp to the planes' borders in space and time, so the MLP sees border features: the
    // same float-vs-double error as inside (measured worst 1.2e-7 relative here).
    test::expect_allclose(ctx.download<float>(d.means, 3 * kN), r.means, {.of_largest = 2e-6}, "d.means");
    test::expect_allclose(ctx.download<float>(d.quats, 4 * kN), r.quats, {.of_largest = 2e-6}, "d.quats");
    test::expect_allclose(ctx.download<float>(d.sh, 48 * kN), r.sh, {.of_largest = 2e-6}, "d.sh");
    Cotangents v = make_cotangents(33);
    run_backward(f, s, v, time);
    const ref::DeformGrads<double> g = ref::deform_backward(f.twin, to_double(s.host), double(time), to_double(v.host));
    // As check_backward's 1e-5. Measured: v_planes 5.3e-7, v_mlp 3.5e-7, v_means exact (outside the
    // box the clamped features do not depend on the mean, so only the cotangent passes through).
    test::expect_allclose(ctx.download<float>(v.v_means, 3 * kN), g.v.means, {.of_largest = 1e-5}, "v.v_means");
    test::expect_allclose(ctx.download<float>(f.gpu.v_planes(), f.gpu.plane_floats()), g.v_planes, {.of_largest = 1e-5}, "f.gpu.v_planes()");
    test::expect_allclose(ctx.download<float>(f.gpu.v_mlp(), f.gpu.mlp_floats()), g.v_mlp, {.of_largest = 1e-5}, "f.gpu.v_mlp()");
  }
}

namespace {

// The field at its extremes (docs/kernel-extremes.md): forward and backward of `f` on `s` at `time`
// against the twin, each array within `rel` of its largest twin value.
void check_against_twin(Field& f, Scene& s, float time, double rel, const char* what) {
  CAPTURE(what);
  engine::Context& ctx = test::context();
  Deformed d = run_forward(f, s, time);
  const ref::DeformGaussians<double> r = ref::deform_forward(f.twin, to_double(s.host), double(time));
  auto close = [&](const std::vector<float>& gpu, const std::vector<double>& twin, const char* name) {
    test::expect_allclose(gpu, twin, {.of_largest = rel}, std::string(what) + ": " + name);
  };
  close(ctx.download<float>(d.means, 3 * kN), r.means, "means");
  close(ctx.download<float>(d.log_scales, 3 * kN), r.log_scales, "log_scales");
  close(ctx.download<float>(d.quats, 4 * kN), r.quats, "quats");
  close(ctx.download<float>(d.opacity, kN), r.opacity_logits, "opacity_logits");
  close(ctx.download<float>(d.sh, 48 * kN), r.sh, "sh");
  Cotangents v = make_cotangents(43);
  run_backward(f, s, v, time);
  const ref::DeformGrads<double> g = ref::deform_backward(f.twin, to_double(s.host), double(time), to_double(v.host));
  close(ctx.download<float>(v.v_means, 3 * kN), g.v.means, "v_means");
  close(ctx.download<float>(f.gpu.v_planes(), f.gpu.plane_floats()), g.v_planes, "v_planes");
  close(ctx.download<float>(f.gpu.v_mlp(), f.gpu.mlp_floats()), g.v_mlp, "v_mlp");
}

// One plane of the field (level 0, plane 0: x-y) set to `value` on the GPU and in the twin.
void set_plane(Field& f, float value) {
  std::vector<float> planes = f.gpu.download_planes();
  const uint32_t at = gpu::deform_plane_offset(f.gpu.shape(), 0, 0);
  std::fill_n(planes.begin() + at, gpu::deform_plane_floats(f.gpu.shape(), 0, 0), value);
  f.gpu.upload_planes(planes);
  f.twin.planes = to_double(planes);
}

}  // namespace

TEST_CASE("times exactly 0 and 1 deform like the twin, forward and backward") {
  for (const float time : {0.0f, 1.0f}) {
    Field f = make_field(test_config(), 41);
    Scene s = make_scene(test_config(), 42, 0);
    // As check_backward's 1e-5 (the time planes' first and last texels, no interpolation). Measured
    // worst on lavapipe (Mesa 22.3.6): 4.3e-7 (forward), 1.7e-6 (v_means at t = 1).
    check_against_twin(f, s, time, 1e-5, time == 0 ? "t = 0" : "t = 1");
  }
}

TEST_CASE("a plane of 1e30 and a plane of denormals deform like the twin, forward and backward") {
  {
    Field f = make_field(test_config(), 44);
    set_plane(f, 1e30f);  // level 0's features near 1e30, the outputs near 1e30: still finite in float
    Scene s = make_scene(test_config(), 45, 0);
    // Measured worst 1.5e-6 (sh) of the largest value; two planes of 1e30 would overflow float.
    check_against_twin(f, s, kTime, 1e-5, "plane of 1e30");
  }
  {
    Field f = make_field(test_config(), 46);
    set_plane(f, 1e-40f);  // lavapipe flushes denormals to 0; the twin keeps them: level 0's features vanish in both
    Scene s = make_scene(test_config(), 47, 0);
    // Measured worst 9.3e-7 (v_planes) of the largest value: denormal or 0, a product of 1e-40 is lost in float rounding.
    check_against_twin(f, s, kTime, 1e-5, "plane of denormals");
  }
}

TEST_CASE("displacements of 1e4 deform like the twin, forward and backward") {
  Field f = make_field(test_config(), 48);
  std::vector<float> mlp = f.gpu.download_mlp();
  for (float& w : mlp) w *= 10.0f;  // through three layers: displacements of about 1e4
  f.gpu.upload_mlp(mlp);
  f.twin.mlp = to_double(mlp);
  Scene s = make_scene(test_config(), 49, 0);
  const ref::DeformGaussians<double> r = ref::deform_forward(f.twin, to_double(s.host), double(kTime));
  double largest = 0;
  for (size_t k = 0; k < r.means.size(); ++k) largest = std::max(largest, std::abs(r.means[k] - s.host.means[k]));
  REQUIRE(largest > 3e3);
  REQUIRE(largest < 3e4);
  // Float sums of terms of 1e3 against double: measured worst 9.4e-7 (v_planes) of the largest value.
  check_against_twin(f, s, kTime, 1e-5, "displacements of 1e4");
}
