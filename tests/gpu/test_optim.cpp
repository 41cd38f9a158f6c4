// The GPU loss (L1 + SSIM, value and image gradient) and Adam against their CPU twins on lavapipe.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "expect_allclose.h"
#include "s4d/engine/buffer_from.h"
#include "s4d/engine/recorder.h"
#include "s4d/optim/adam.h"
#include "s4d/optim/grad_mask.h"
#include "s4d/optim/image_loss.h"
#include "s4d/optim/tv_loss.h"
#include "s4d/primitives/add.h"
#include "s4d/primitives/shader_pipeline.h"
#include "s4d/ref/adam_ref.h"
#include "s4d/ref/loss_ref.h"
#include "s4d_loss.h"
#include "test_context.h"

namespace {

using namespace s4d;

std::vector<float> random_values(size_t n, unsigned seed, float lo = 0, float hi = 1) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(lo, hi);
  std::vector<float> v(n);
  for (float& x : v) x = u(rng);
  return v;
}

}  // namespace

TEST_CASE("GPU L1 + SSIM loss and gradient match the twin") {
  for (const auto& [w, h, c] : {std::array<int, 3>{37, 23, 3}, std::array<int, 3>{5, 4, 1}, std::array<int, 3>{64, 48, 3}}) {
    CAPTURE(w);
    CAPTURE(h);
    const size_t n = static_cast<size_t>(w * h * c);
    const std::vector<float> x = random_values(n, 1), y = random_values(n, 2);
    engine::Buffer bx = engine::buffer_from(test::context(), "image", x), by = engine::buffer_from(test::context(), "target", y), grad = engine::buffer_from(test::context(), "grad", std::vector<float>(n, 0));
    optim::ImageLoss loss(test::context());
    engine::Recorder rec(test::context(), "loss");
    loss.record(rec, bx, by, static_cast<uint32_t>(w), static_cast<uint32_t>(h), static_cast<uint32_t>(c), 0.2f, grad);
    test::context().run(std::move(rec));
    const optim::LossValue v = loss.value();
    const std::vector<float> g = test::context().download<float>(grad, n);

    const std::vector<double> xd(x.begin(), x.end()), yd(y.begin(), y.end());
    const auto t = ref::l1_ssim_loss(xd, yd, w, h, c, 0.2);
    // Float sums over up to 9216 elements against a double twin: measured 3e-7 relative.
    CHECK(v.loss == doctest::Approx(t.loss).epsilon(1e-5));
    CHECK(v.ssim == doctest::Approx(t.ssim).epsilon(1e-5));
    CHECK(v.l1 == doctest::Approx(t.l1).epsilon(1e-5));
    // 121-tap float filters of the dS maps; measured 2e-6 relative.
    test::expect_allclose(g, t.grad, {.of_largest = 1e-4}, "grad");
  }
}

TEST_CASE("GPU Adam matches the twin over several steps with two parameter groups") {
  const size_t n = 1000;
  std::vector<float> p = random_values(n, 3, -1, 1), q = random_values(n, 4, -1, 1);
  engine::Buffer bp = engine::buffer_from(test::context(), "p", p), bq = engine::buffer_from(test::context(), "q", q);
  engine::Buffer mp = engine::buffer_from(test::context(), "mp", std::vector<float>(n, 0)), vp = engine::buffer_from(test::context(), "vp", std::vector<float>(n, 0));
  engine::Buffer mq = engine::buffer_from(test::context(), "mq", std::vector<float>(n, 0)), vq = engine::buffer_from(test::context(), "vq", std::vector<float>(n, 0));
  std::vector<double> pd(p.begin(), p.end()), qd(q.begin(), q.end()), m1(n), v1(n), m2(n), v2(n);
  optim::Adam adam(test::context(), 2);
  const optim::AdamSettings sp{.lr = 0.01, .beta1 = 0.9, .beta2 = 0.999, .eps = 1e-15};
  const optim::AdamSettings sq{.lr = 0.05, .beta1 = 0.8, .beta2 = 0.99, .eps = 1e-8};
  for (uint32_t step = 1; step <= 5; ++step) {
    const std::vector<float> gp = random_values(n, 10 + step, -1, 1), gq = random_values(n, 20 + step, -1, 1);
    engine::Buffer bgp = engine::buffer_from(test::context(), "gp", gp), bgq = engine::buffer_from(test::context(), "gq", gq);
    adam.set_group(0, sp, step);
    adam.set_group(1, sq, step);
    adam.upload();
    engine::Recorder rec(test::context(), "adam");
    adam.record(rec, 0, bp, bgp, mp, vp, static_cast<uint32_t>(n));
    adam.record(rec, 1, bq, bgq, mq, vq, static_cast<uint32_t>(n));
    test::context().run(std::move(rec));
    ref::adam_step(pd, std::vector<double>(gp.begin(), gp.end()), m1, v1, {sp.lr, sp.beta1, sp.beta2, sp.eps}, static_cast<int>(step));
    ref::adam_step(qd, std::vector<double>(gq.begin(), gq.end()), m2, v2, {sq.lr, sq.beta1, sq.beta2, sq.eps}, static_cast<int>(step));
  }
  const std::vector<float> gpu_p = test::context().download<float>(bp, n), gpu_q = test::context().download<float>(bq, n);
  // Float vs double over 5 steps of size <= 0.05; measured 6e-8.
  test::expect_allclose(gpu_p, pd, {.atol = 1e-5}, "group 0");
  test::expect_allclose(gpu_q, qd, {.atol = 1e-5}, "group 1");
}

TEST_CASE("GPU Adam splits rows between two groups like the twin (SH DC and rest)") {
  const uint32_t rows = 300, row = 12, head = 3;  // degree-1 SH rows: 3 DC floats, 9 higher
  const size_t n = size_t{rows} * row;
  std::vector<float> p = random_values(n, 31, -1, 1);
  engine::Buffer bp = engine::buffer_from(test::context(), "sh", p);
  engine::Buffer m = engine::buffer_from(test::context(), "m", std::vector<float>(n, 0)), v = engine::buffer_from(test::context(), "v", std::vector<float>(n, 0));
  std::vector<double> pd(p.begin(), p.end()), md(n), vd(n);
  optim::Adam adam(test::context(), 2);
  const optim::AdamSettings dc{.lr = 0.0025}, rest{.lr = 0.000125};
  for (uint32_t step = 1; step <= 3; ++step) {
    const std::vector<float> g = random_values(n, 40 + step, -1, 1);
    engine::Buffer bg = engine::buffer_from(test::context(), "g", g);
    adam.set_group(0, dc, step);
    adam.set_group(1, rest, step);
    adam.upload();
    engine::Recorder rec(test::context(), "adam rows");
    adam.record_rows(rec, 0, 1, row, head, bp, bg, m, v, static_cast<uint32_t>(n));
    test::context().run(std::move(rec));
    ref::adam_step_rows(pd, std::vector<double>(g.begin(), g.end()), md, vd, row, head, {dc.lr, dc.beta1, dc.beta2, dc.eps},
                        {rest.lr, rest.beta1, rest.beta2, rest.eps}, static_cast<int>(step));
  }
  const std::vector<float> out = test::context().download<float>(bp, n);
  test::expect_allclose(out, pd, {.atol = 1e-6}, "sh");  // float vs double over 3 steps of size <= 0.0025; measured 8.7e-8
  // The groups really differ: a DC element moved about 20x further than a higher coefficient.
  CHECK(std::abs(out[0] - p[0]) > 10 * std::abs(out[head] - p[head]));
  engine::Recorder bad(test::context(), "bad rows");
  CHECK_THROWS_AS(adam.record_rows(bad, 0, 1, row, row + 1, bp, bp, m, v, static_cast<uint32_t>(n)), std::invalid_argument);
}

TEST_CASE("grad_add sums a batch's gradients exactly like the twin (a float add per element)") {
  const uint32_t n = 1000;
  const std::vector<float> a = random_values(n, 51, -1, 1), b = random_values(n, 52, -1, 1);
  engine::Buffer da = engine::buffer_from(test::context(), "dst", a), db = engine::buffer_from(test::context(), "src", b);
  engine::Recorder rec(test::context(), "grad_add");
  primitives::cmd_add(rec, da, db, n - 1);  // the last element stays: n is honoured
  test::context().run(std::move(rec));
  const std::vector<float> out = test::context().download<float>(da, n);
  for (uint32_t i = 0; i + 1 < n; ++i) CHECK(out[i] == a[i] + b[i]);  // one IEEE float add: exact
  CHECK(out[n - 1] == a[n - 1]);
  engine::Recorder bad(test::context(), "bad grad_add");
  CHECK_THROWS_AS(primitives::cmd_add(bad, da, db, n + 1), std::invalid_argument);
}

// Kernel tv_grad (TvLoss).
TEST_CASE("GPU TV term adds the twin's gradient to the existing one and reports its value") {
  for (const auto& [w, h, c] : {std::array<int, 3>{37, 23, 3}, std::array<int, 3>{2, 2, 1}, std::array<int, 3>{64, 48, 3}}) {
    CAPTURE(w);
    CAPTURE(h);
    const ref::LossShape shape{w, h, c};
    const std::vector<float> x = random_values(shape.n(), 4), g0 = random_values(shape.n(), 5, -1, 1);
    engine::Buffer bx = engine::buffer_from(test::context(), "image", x), grad = engine::buffer_from(test::context(), "grad", g0);
    optim::TvLoss tv(test::context());
    engine::Recorder rec(test::context(), "tv");
    tv.record(rec, bx, static_cast<uint32_t>(w), static_cast<uint32_t>(h), static_cast<uint32_t>(c), 0.3f, grad);
    test::context().run(std::move(rec));
    const std::vector<float> g = test::context().download<float>(grad, shape.n());
    const auto [value, tg] = ref::tv_loss(std::vector<double>(x.begin(), x.end()), shape, 0.3);
    CHECK(tv.value() == doctest::Approx(value).epsilon(1e-5));  // float partial sums; measured 3.7e-8 relative
    std::vector<double> want(shape.n());
    for (size_t e = 0; e < shape.n(); ++e) want[e] = g0[e] + tg[e];
    test::expect_allclose(g, want, {.atol = 1e-6}, "grad");  // float rounding of values in [-1, 1]: measured 3e-8
  }
  optim::TvLoss tv(test::context());
  engine::Buffer one = engine::buffer_from(test::context(), "one pixel", std::vector<float>(3, 0));
  engine::Recorder rec(test::context(), "tv");
  CHECK_THROWS_AS(tv.record(rec, one, 1, 1, 3, 1.0f, one), std::invalid_argument);
}

TEST_CASE("grad_mask zeroes exactly the rows whose mask is 0 and keeps the others bit for bit") {
  const uint32_t rows = 300, row = 52;
  const std::vector<float> values = random_values(size_t{rows} * row, 6, -1, 1);
  std::vector<uint32_t> mask(rows);
  for (uint32_t i = 0; i < rows; ++i) mask[i] = (i * 7) % 3 == 0 ? 0u : i;
  engine::Buffer bv = engine::buffer_from(test::context(), "values", values), bm = engine::buffer_from(test::context(), "mask", mask);
  engine::Recorder rec(test::context(), "mask");
  optim::record_grad_mask(rec, bv, bm, rows, row);
  test::context().run(std::move(rec));
  const std::vector<float> out = test::context().download<float>(bv, values.size());
  for (size_t i = 0; i < values.size(); ++i) CHECK(out[i] == (mask[i / row] == 0 ? 0.0f : values[i]));
  engine::Recorder bad(test::context(), "mask");
  CHECK_THROWS_AS(optim::record_grad_mask(bad, bv, bm, rows + 1, row), std::invalid_argument);
}

TEST_CASE("each loss kernel matches its twin on the same inputs: ssim_hpass, ssim_vpass, loss_grad") {
  const ref::LossShape s{29, 17, 3};
  const size_t n = s.n();
  const uint32_t groups = static_cast<uint32_t>((n + S4D_LOSS_WG - 1) / S4D_LOSS_WG);
  const std::vector<float> x = random_values(n, 5), y = random_values(n, 6);
  const std::vector<float> dmaps_in = random_values(3 * n, 7, -1e-3f, 1e-3f);
  engine::Context& ctx = test::context();
  engine::Buffer bx = engine::buffer_from(test::context(), "x", x), by = engine::buffer_from(test::context(), "y", y), bdmaps_in = engine::buffer_from(test::context(), "dmaps in", dmaps_in);
  engine::Buffer stats_h(ctx, "stats_h", 5 * n * 4), dmaps(ctx, "dmaps", 3 * n * 4), dmaps_h(ctx, "dmaps_h", 3 * n * 4);
  engine::Buffer partials(ctx, "partials", 2 * size_t{groups} * 4), grad(ctx, "grad", n * 4);
  gpu::LossParams p{.width = 29, .height = 17, .channels = 3, .n = static_cast<uint32_t>(n), .ssim_weight = 0.2f,
                    .inv_count = 1.0f / static_cast<float>(n), .mode = 0, ._pad0 = 0};
  engine::Recorder rec(ctx, "loss kernels");
  rec.dispatch(primitives::shader_pipeline(ctx, shaders::Id::ssim_hpass),
               {S4D_BIND(SSIM_H_IN_A, bx), S4D_BIND(SSIM_H_IN_B, by), S4D_BIND(SSIM_H_OUT, stats_h)}, p, groups);
  rec.barrier();
  rec.dispatch(primitives::shader_pipeline(ctx, shaders::Id::ssim_vpass),
               {S4D_BIND(SSIM_V_IMAGE, bx), S4D_BIND(SSIM_V_TARGET, by), S4D_BIND(SSIM_V_STATS_H, stats_h),
                S4D_BIND(SSIM_V_DMAPS, dmaps), S4D_BIND(SSIM_V_PARTIALS, partials)},
               p, groups);
  p.mode = 1;
  rec.dispatch(primitives::shader_pipeline(ctx, shaders::Id::ssim_hpass),
               {S4D_BIND(SSIM_H_IN_A, bdmaps_in), S4D_BIND(SSIM_H_IN_B, bdmaps_in), S4D_BIND(SSIM_H_OUT, dmaps_h)}, p,
               groups);
  rec.barrier();
  rec.dispatch(primitives::shader_pipeline(ctx, shaders::Id::loss_grad),
               {S4D_BIND(LOSS_GRAD_IMAGE, bx), S4D_BIND(LOSS_GRAD_TARGET, by), S4D_BIND(LOSS_GRAD_DMAPS_H, dmaps_h),
                S4D_BIND(LOSS_GRAD_OUT, grad)},
               p, groups);
  ctx.run(std::move(rec));

  // Each twin is fed the GPU's own input to that kernel, so only float rounding in an 11-tap
  // filter (and the SSIM quotient) remains. Measured relative to each array's largest entry:
  // ssim_hpass statistics 1.4e-7, ssim_vpass maps 1.9e-7, ssim_hpass maps and loss_grad 0.
  const std::vector<float> gpu_stats = ctx.download<float>(stats_h, 5 * n);
  test::expect_allclose(gpu_stats, ref::ssim_hpass_stats(x, y, s), {.of_largest = 1e-6}, "gpu_stats");
  const auto v = ref::ssim_vpass(x, y, gpu_stats, s, 0.2f);
  test::expect_allclose(ctx.download<float>(dmaps, 3 * n), v.dmaps, {.of_largest = 1e-6}, "dmaps");
  const std::vector<float> part = ctx.download<float>(partials, 2 * size_t{groups});
  double ssim_sum = 0, l1_sum = 0;
  for (uint32_t g = 0; g < groups; ++g) ssim_sum += part[2 * g], l1_sum += part[2 * g + 1];
  CHECK(ssim_sum == doctest::Approx(v.ssim_sum).epsilon(1e-5));
  CHECK(l1_sum == doctest::Approx(v.l1_sum).epsilon(1e-5));
  const std::vector<float> gpu_dmaps_h = ctx.download<float>(dmaps_h, 3 * n);
  test::expect_allclose(gpu_dmaps_h, ref::ssim_hpass_dmaps(dmaps_in, s), {.of_largest = 1e-6}, "gpu_dmaps_h");
  test::expect_allclose(ctx.download<float>(grad, n), ref::loss_grad(x, y, gpu_dmaps_h, s, 0.2f), {.of_largest = 1e-6}, "grad");
}
