// Numerical extremes of the style MLP (ALGORITHMS.md 4.3, docs/kernel-extremes.md): weights large
// enough to saturate every sigmoid, a time far outside [0, 1], a huge relative-depth scale and hit
// depths near 0, negative, absent and at 1e30. The render and every gradient stay finite and equal
// the CPU twin end to end.
#include <doctest/doctest.h>

#include <array>
#include <cmath>
#include <random>
#include <vector>

#include "expect_allclose.h"
#include "style_harness.h"
#include "test_context.h"

namespace {

using namespace s4d;

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
    const auto tf = ref::render_style_fwd(g, mlp, cam, bg);
    const auto tg = ref::render_style_bwd(g, mlp, cam, bg, tf, v);
    // Saturated sigmoids are exactly 0 or 1 in both, so the colour offsets are +-1 and the MLP's
    // gradients vanish but for the last layer's bias path; measured as the unsaturated end-to-end test.
    test::expect_allclose(f.img.rgb, tf.img.rgb, {.of_largest = 1e-5}, "f.img.rgb");
    test::expect_allclose(f.img.alpha, tf.img.alpha, {.of_largest = 1e-5}, "f.img.alpha");
    test::expect_allclose(v_mlp, tg.v_mlp, {.of_largest = 1e-5}, "v_mlp");
    test::expect_allclose(b.grads.v_means, tg.g.v_means, {.of_largest = 1e-5}, "b.grads.v_means");
    test::expect_allclose(b.grads.v_opacity_logits, tg.g.v_opacity_logits, {.of_largest = 1e-5}, "b.grads.v_opacity_logits");
  }
}

// The MLP's depth input t* at its extremes (docs/kernel-extremes.md), each from a Gaussian's shape
// seen through the 16x16 tile camera: a needle along the view axis puts t* near 0 (1e-6 of its
// depth), the same needle off the axis puts it behind the camera (negative) on one side, scales of
// 1e20 leave no quadric (Q = 0: absent, the centre depth is used), and a Gaussian 1e30 away puts it
// at 1e30. Both depth features, with and without the input sigmoid.
TEST_CASE("hit depths near 0, negative, absent and 1e30 give the style MLP the twin's inputs") {
  const test::Cam cam = test::tile_camera();
  for (const ref::StyleDepth depth : {ref::StyleDepth::ndc, ref::StyleDepth::relative})
    for (const bool sigmoid : {false, true}) {
      CAPTURE(static_cast<int>(depth));
      CAPTURE(sigmoid);
      std::mt19937 rng(31);
      test::Scene g;
      g.sh_degree = 0;
      test::add_gaussian(g, cam, 8.0f, 8.0f, 3.0f, 2.0f, 0.6f, rng);   // needle on the axis
      test::add_gaussian(g, cam, 4.0f, 8.0f, 3.0f, 2.0f, 0.6f, rng);   // needle off the axis
      test::add_gaussian(g, cam, 10.0f, 6.0f, 4.0f, 3.0f, 0.5f, rng);  // no quadric
      test::add_gaussian(g, cam, 7.0f, 9.0f, 5.0f, 1.0f, 0.9f, rng);   // moved 1e30 away below
      for (size_t i : {0, 1}) g.log_scales[3 * i + 2] = std::log(1e4f);
      for (size_t k = 6; k < 9; ++k) g.log_scales[k] = std::log(1e20f);
      g.means[3 * 3 + 2] = 1e30f;
      if (depth == ref::StyleDepth::ndc && !sigmoid) {  // the cases are what they claim: t* from the twin's quadrics
        const std::vector<float> q = ref::style_quadric(g, cam);
        ref::StyleMlp<float> unit;
        unit.depth = ref::StyleDepth::relative;  // feature t* - z at depth_scale 1
        auto hit = [&](size_t i, float rx, float ry) {
          const float z = g.means[3 * i + 2];
          return ref::detail::style_depth_feature(&q[ref::kStyleQuadricStride * i], z, rx, ry, unit) + z;
        };
        CHECK(std::abs(hit(0, 0.03f, 0.03f)) < 1e-5f);
        CHECK(hit(1, 0.1f, 0.0f) < 0.0f);
        for (size_t k = 0; k < 9; ++k) CHECK(q[ref::kStyleQuadricStride * 2 + k] == 0.0f);
        CHECK(hit(3, 0.01f, 0.01f) > 1e29f);
      }
      test::DeviceScene dev(test::context(), g);
      ref::StyleMlp<float> mlp = test::random_mlp(g.size(), depth, sigmoid, rng);
      test::DeviceStyle style(test::context(), mlp);
      style.attach(dev);
      splat::Rasterizer r(test::context());
      constexpr std::array<float, 3> bg = {0.2f, 0.1f, 0.4f};
      const test::GpuForward f = test::gpu_forward(r, dev, cam, bg);
      const auto v = test::random_cotangents(cam, rng, true);
      const test::GpuBackward b = test::gpu_backward(r, dev, v, f.img.alpha.size());
      const auto tf = ref::render_style_fwd(g, mlp, cam, bg);
      const auto tg = ref::render_style_bwd(g, mlp, cam, bg, tf, v);
      // Measured worst on lavapipe (Mesa 22.3.6): rgb and alpha 2.4e-7; gradients, which reach 1e24 (v_mlp
      // of the relative feature without a sigmoid) and 1e28 (v_means of the Gaussian 1e30 away), 5.8e-6
      // relative.
      test::expect_allclose(f.img.rgb, tf.img.rgb, {.atol = 1e-5, .rtol = 1e-5}, "rgb");
      test::expect_allclose(f.img.alpha, tf.img.alpha, {.atol = 1e-5, .rtol = 1e-5}, "alpha");
      test::expect_allclose(style.download_v_mlp(test::context()), tg.v_mlp, {.atol = 1e-5, .rtol = 3e-5}, "v_mlp");
      test::expect_allclose(b.grads.v_means, tg.g.v_means, {.atol = 1e-5, .rtol = 3e-5}, "v_means");
    }
}
