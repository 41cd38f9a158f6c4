// Numerical extremes of the style MLP (ALGORITHMS.md 4.3): weights large enough to saturate every
// sigmoid, a time far outside [0, 1] and a huge relative-depth scale. The render and every gradient
// stay finite and equal the CPU twin end to end.
#include <doctest/doctest.h>

#include <cmath>
#include <random>
#include <vector>

#include "style_harness.h"
#include "test_context.h"

namespace {

using namespace s4d;

bool all_finite(const std::vector<float>& v) {
  for (float x : v)
    if (!std::isfinite(x)) return false;
  return true;
}

}  // namespace

TEST_CASE("a saturated style MLP at an extreme time renders and differentiates finitely, like the twin") {
  constexpr std::array<float, 3> bg = {0.1f, 0.3f, 0.6f};
  for (const bool sigmoid : {false, true}) {
    CAPTURE(sigmoid);
    std::mt19937 rng(29);
    const test::Cam cam = test::random_camera(48, 32, rng);
    const test::Scene g = test::random_scene(200, 1, false, rng);
    ref::StyleMlp<float> mlp = test::random_mlp(g.size(), ref::StyleDepth::relative, sigmoid, rng);
    for (float& w : mlp.weights) w *= 1e4f;  // every pre-activation far past float exp's range (~88)
    mlp.time = 1e6f;
    mlp.depth_scale = 1e8f;
    test::DeviceScene dev(test::context(), g);
    test::DeviceStyle style(test::context(), mlp);
    style.attach(dev);
    splat::Rasterizer r(test::context());
    const test::GpuForward f = test::gpu_forward(r, dev, cam, bg);
    const auto v = test::random_cotangents(cam, rng, true);
    const test::GpuBackward b = test::gpu_backward(r, dev, v, f.img.alpha.size());
    const std::vector<float> v_mlp = style.download_v_mlp(test::context());
    REQUIRE(all_finite(f.img.rgb));
    REQUIRE(all_finite(f.img.alpha));
    REQUIRE(all_finite(v_mlp));
    REQUIRE(all_finite(b.grads.v_means));
    REQUIRE(all_finite(b.grads.v_opacity_logits));
    const auto tf = ref::render_style_fwd(g, mlp, cam, bg);
    const auto tg = ref::render_style_bwd(g, mlp, cam, bg, tf, v);
    // Saturated sigmoids are exactly 0 or 1 in both, so the colour offsets are +-1 and the MLP's
    // gradients vanish but for the last layer's bias path; measured as the unsaturated end-to-end test.
    CHECK(test::rel_err(f.img.rgb, tf.img.rgb) <= 1e-5);
    CHECK(test::rel_err(f.img.alpha, tf.img.alpha) <= 1e-5);
    CHECK(test::rel_err(v_mlp, tg.v_mlp) <= 1e-5);
    CHECK(test::rel_err(b.grads.v_means, tg.g.v_means) <= 1e-5);
    CHECK(test::rel_err(b.grads.v_opacity_logits, tg.g.v_opacity_logits) <= 1e-5);
  }
}
