// Numerical extremes of the optimizer kernels on lavapipe (docs/kernel-extremes.md): Adam with zero,
// huge and infinite gradients and a learning rate of 0, and the L1 + SSIM loss on black, white and
// constant frames and on 1x1 and 16384-pixel-wide images. Every output is finite and equals the CPU twin; a huge gradient moves a parameter by lr.
#include <doctest/doctest.h>

#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "expect_allclose.h"
#include "s4d/engine/buffer_from.h"
#include "s4d/engine/recorder.h"
#include "s4d/optim/adam.h"
#include "s4d/optim/image_loss.h"
#include "s4d/ref/adam_ref.h"
#include "s4d/ref/loss_ref.h"
#include "test_context.h"

namespace {

using namespace s4d;

struct AdamRun {
  std::vector<float> p, m, v;
};

// `steps` Adam steps of `lr` on `p` with the same gradients each step, from zero moments.
AdamRun gpu_adam(const std::vector<float>& p0, const std::vector<float>& g, uint32_t steps, double lr = 0.01) {
  engine::Context& ctx = test::context();
  const size_t n = p0.size();
  engine::Buffer p = engine::buffer_from(ctx, "p", p0), grad = engine::buffer_from(ctx, "g", g);
  engine::Buffer m = engine::buffer_from(ctx, "m", std::vector<float>(n, 0)), v = engine::buffer_from(ctx, "v", std::vector<float>(n, 0));
  optim::Adam adam(ctx, 1);
  for (uint32_t step = 1; step <= steps; ++step) {
    adam.set_group(0, {.lr = lr, .beta1 = 0.9, .beta2 = 0.999, .eps = 1e-15}, step);
    adam.upload();
    engine::Recorder rec(ctx, "adam");
    adam.record(rec, 0, p, grad, m, v, static_cast<uint32_t>(n));
    ctx.run(std::move(rec));
  }
  return {ctx.download<float>(p, n), ctx.download<float>(m, n), ctx.download<float>(v, n)};
}

}  // namespace

TEST_CASE("Adam with zero gradients from zero moments leaves parameters bit for bit and moments at 0") {
  const std::vector<float> p0 = {-3.5f, 0.0f, 1e-30f, 7.25f, -0.0f, 1e30f};
  const AdamRun r = gpu_adam(p0, std::vector<float>(p0.size(), 0.0f), 3);
  for (size_t i = 0; i < p0.size(); ++i) {
    CAPTURE(i);
    CHECK(r.p[i] == p0[i]);
    CHECK(r.m[i] == 0.0f);
    CHECK(r.v[i] == 0.0f);
  }
}

TEST_CASE("Adam with huge and infinite gradients moves each parameter by lr like any first step, moments finite") {
  const float big = std::numeric_limits<float>::max(), inf = std::numeric_limits<float>::infinity();
  const std::vector<float> g = {1e18f, 1e19f, -3e20f, 1e30f, -1e38f, big, -big, inf, -inf, 1.0f, -2.0f};
  const std::vector<float> p0(g.size(), 0.5f);
  const AdamRun r = gpu_adam(p0, g, 1);
  std::vector<double> pd(p0.begin(), p0.end()), md(g.size()), vd(g.size());
  ref::adam_step(pd, std::vector<double>(g.begin(), g.end()), md, vd, {0.01, 0.9, 0.999, 1e-15}, 1);
  for (size_t i = 0; i < g.size(); ++i) {
    CAPTURE(g[i]);
    REQUIRE(std::isfinite(r.m[i]));
    REQUIRE(std::isfinite(r.v[i]));
    // A first Adam step is lr x sign(g) whatever |g| (m_hat / sqrt(v_hat) = g / |g|); the float
    // kernel and the double twin agree to rounding: measured 0 difference at p = 0.5, lr = 0.01.
    CHECK(r.p[i] == doctest::Approx(0.5 - 0.01 * (g[i] > 0 ? 1 : -1)).epsilon(1e-6));
    CHECK(r.p[i] == doctest::Approx(pd[i]).epsilon(1e-6));
    // v carries float's 1 - beta2 (0.0010000467 for 0.999): measured 1.3e-5 relative.
    CHECK(r.v[i] == doctest::Approx(vd[i]).epsilon(1e-4));
  }
}

TEST_CASE("Adam passes a NaN gradient through to the parameter for the trainer's rollback to see") {
  const AdamRun r = gpu_adam({0.5f}, {std::numeric_limits<float>::quiet_NaN()}, 1);
  CHECK(std::isnan(r.p[0]));
}

TEST_CASE("Adam with a learning rate of 0 keeps every parameter bit for bit and still updates the moments like the twin") {
  const float inf = std::numeric_limits<float>::infinity();
  const std::vector<float> g = {0.0f, 1e-3f, -2.0f, 1e38f, inf};
  const std::vector<float> p0 = {0.5f, -7.0f, 1e30f, 0.0f, 3.0f};
  const AdamRun r = gpu_adam(p0, g, 2, 0.0);
  std::vector<double> pd(p0.begin(), p0.end()), md(g.size()), vd(g.size());
  for (uint32_t step = 1; step <= 2; ++step)
    ref::adam_step(pd, std::vector<double>(g.begin(), g.end()), md, vd, {0.0, 0.9, 0.999, 1e-15}, step);
  s4d::test::expect_allclose(r.p, p0, {}, "p at lr 0");
  // m: float (1 - beta1) and sums against double, measured worst 2.2e-7 relative; v as above (float's
  // 1 - beta2): measured 1.3e-5 relative.
  s4d::test::expect_allclose(r.m, md, {.rtol = 1e-6}, "m at lr 0");
  s4d::test::expect_allclose(r.v, vd, {.rtol = 1e-4}, "v at lr 0");
}

TEST_CASE("L1 + SSIM on black, constant, 1x1 and 16384-wide images is finite and equals the twin") {
  struct Case {
    const char* name;
    int w, h;
    float image, target;  // constant values
  };
  const std::array<Case, 6> cases = {{{"black on black", 32, 24, 0.0f, 0.0f},
                                      {"black on white", 32, 24, 0.0f, 1.0f},
                                      {"grey on grey", 32, 24, 0.5f, 0.5f},
                                      {"white on white", 32, 24, 1.0f, 1.0f},
                                      {"1x1", 1, 1, 0.25f, 0.75f},
                                      {"16384x2", 16384, 2, 0.9f, 0.1f}}};
  for (const Case& k : cases) {
    CAPTURE(k.name);
    const size_t n = static_cast<size_t>(k.w) * k.h * 3;
    std::vector<float> x(n, k.image), y(n, k.target);
    x[0] = std::min(1.0f, k.image + 0.125f);  // one pixel off the constant, so the gradient has structure
    engine::Context& ctx = test::context();
    engine::Buffer bx = engine::buffer_from(ctx, "image", x), by = engine::buffer_from(ctx, "target", y),
                   grad = engine::buffer_from(ctx, "grad", std::vector<float>(n, 0));
    optim::ImageLoss loss(ctx);
    engine::Recorder rec(ctx, "loss");
    loss.record(rec, bx, by, static_cast<uint32_t>(k.w), static_cast<uint32_t>(k.h), 3, 0.2f, grad);
    ctx.run(std::move(rec));
    const optim::LossValue v = loss.value();
    const std::vector<float> g = ctx.download<float>(grad, n);
    const auto t = ref::l1_ssim_loss(std::vector<double>(x.begin(), x.end()), std::vector<double>(y.begin(), y.end()),
                                     k.w, k.h, 3, 0.2);
    // Float against double sums of up to 98,304 equal terms: measured 4e-7 relative.
    CHECK(v.loss == doctest::Approx(t.loss).epsilon(1e-5));
    CHECK(v.ssim == doctest::Approx(t.ssim).epsilon(1e-5));
    // As the random-image test: measured 2e-6 relative.
    s4d::test::expect_allclose(g, t.grad, {.atol = 1e-12, .of_largest = 1e-4}, "grad");
  }
}
