// The fused style rasterizer on lavapipe against its CPU twin (style_raster_ref.h): the quadrics,
// blending and both backward kernels stage by stage (the twin fed the GPU's own projection and
// quadrics, so tile lists and t* inputs are identical), for both depth modes, with and without the
// input sigmoid, SH and the colour override, float atomics and the compare-and-swap path; and once
// end to end on the twin's own preprocess.
#include <doctest/doctest.h>

#include <random>
#include <vector>

#include "expect_allclose.h"
#include "expect_equal.h"
#include "style_harness.h"
#include "test_context.h"

namespace {

using namespace s4d;
using test::Cam;
using test::Scene;

constexpr std::array<float, 3> kBg = {0.1f, 0.3f, 0.6f};

struct Case {
  ref::StyleDepth depth;
  bool sigmoid;      // input sigmoid
  bool colors;       // colour buffer instead of SH
  bool cas;          // compare-and-swap atomics instead of float atomics
  bool alpha_depth;  // cotangents on the alpha and depth outputs too
  uint32_t pixels = 0;  // pixels per invocation, forward and backward: 0 by device (8 on lavapipe), or the GPUs' 1
  // The fewest subgroup lanes the backward assumes: 0 the device's (8 on lavapipe: the
  // reduce-scatter); 1 or 4, below the subgroup's 8, take the subgroupAdd path that a device whose
  // subgroups vary in size takes.
  uint32_t min_lanes = 0;
};

}  // namespace

// Tolerances: the GPU and the twin evaluate the same float formulas in the same order up to
// exp/division rounding, FMA contraction outside `precise` values and the atomics' order. Measured
// worst cases over the four cases (lavapipe, Mesa 22.3.6): quadric 4.6e-7, blending 4.8e-7,
// grad2d 5.9e-7, MLP gradients 8.4e-7, parameters 7.3e-7. 1e-5 leaves a 12x margin and still
// catches any wrong term (those are O(1) relative errors).
TEST_CASE("GPU style rasterizer matches the twin stage by stage") {
  const ref::StyleDepth ndc = ref::StyleDepth::ndc, rel = ref::StyleDepth::relative;
  for (const Case c : {Case{ndc, false, false, false, true}, Case{ndc, true, false, true, false},
                       Case{rel, false, true, false, false}, Case{rel, true, false, true, true},
                       Case{ndc, false, true, false, true, 1}, Case{rel, true, false, true, true, 1},
                       Case{ndc, true, false, false, true, 0, 1}, Case{rel, false, false, true, true, 1, 4}}) {
    CAPTURE(static_cast<int>(c.depth));
    CAPTURE(c.sigmoid);
    CAPTURE(c.colors);
    CAPTURE(c.cas);
    CAPTURE(c.pixels);
    CAPTURE(c.min_lanes);
    std::mt19937 rng(static_cast<unsigned>(200 + 4 * static_cast<int>(c.depth) + 2 * c.sigmoid + c.cas + 11 * c.pixels +
                                           13 * c.min_lanes));
    const Cam cam = test::random_camera(83, 61, rng);  // not multiples of 16: partial tiles
    const Scene g = test::random_scene(700, 2, c.colors, rng);
    ref::StyleMlp<float> mlp = test::random_mlp(g.size(), c.depth, c.sigmoid, rng);
    mlp.depth_scale = 1.0f / (3.0f * 0.05f);  // 1 / (3 x the scene's typical scale)
    test::DeviceScene dev(test::context(), g);
    test::DeviceStyle style(test::context(), mlp);
    style.attach(dev);
    splat::Rasterizer r(test::context(), "style raster",
                        {.force_cas_atomics = c.cas, .backward_pixels = c.pixels, .forward_pixels = c.pixels,
                         .min_subgroup_lanes = c.min_lanes});
    const test::GpuForward f = test::gpu_forward(r, dev, cam, kBg);

    const std::vector<float> quadric =
        test::context().download<float>(r.quadric(), ref::kStyleQuadricStride * g.size());
    test::expect_allclose(quadric, ref::style_quadric(g, cam), {.of_largest = 1e-5}, "quadric");

    // Blending on the GPU's own projection and quadrics, so the lists and t* inputs are identical.
    const ref::Image<float> ti = ref::style_raster_fwd(f.proj, quadric, mlp, cam, kBg);
    test::expect_allclose(f.img.rgb, ti.rgb, {.atol = 1e-5}, "f.img.rgb");
    test::expect_allclose(f.img.alpha, ti.alpha, {.atol = 1e-5}, "f.img.alpha");
    test::expect_allclose(f.img.depth, ti.depth, {.of_largest = 1e-5}, "f.img.depth");
    test::expect_equal_arrays(f.img.count, ti.count, "contributors per pixel");

    const auto v = test::random_cotangents(cam, rng, c.alpha_depth);
    const test::GpuBackward b = test::gpu_backward(r, dev, v, ti.alpha.size());
    const std::vector<float> v_mlp = style.download_v_mlp(test::context());
    const ref::StyleRasterGrads<float> tg2 = ref::style_raster_bwd(f.proj, quadric, mlp, cam, kBg, ti, v);
    test::expect_allclose(b.grad2d.v_mean2d, tg2.g2d.v_mean2d, {.of_largest = 1e-5}, "b.grad2d.v_mean2d");
    test::expect_allclose(b.grad2d.v_conic, tg2.g2d.v_conic, {.of_largest = 1e-5}, "b.grad2d.v_conic");
    test::expect_allclose(b.grad2d.v_opacity, tg2.g2d.v_opacity, {.of_largest = 1e-5}, "b.grad2d.v_opacity");
    test::expect_allclose(b.grad2d.v_rgb, tg2.g2d.v_rgb, {.of_largest = 1e-5}, "b.grad2d.v_rgb");
    test::expect_allclose(b.grad2d.v_depth, tg2.g2d.v_depth, {.of_largest = 1e-5}, "b.grad2d.v_depth");
    test::expect_allclose(v_mlp, tg2.v_mlp, {.of_largest = 1e-5}, "v_mlp");
    // The preprocess backward is the plain one, on the GPU's grad2d.
    const ref::GaussianGrads<float> tg = ref::project_bwd(g, cam, f.proj, b.grad2d);
    test::expect_param_grads_allclose(b.grads, tg, c.colors, {.of_largest = 1e-5});
  }
}

TEST_CASE("GPU style render and gradients match the twin end to end") {
  std::mt19937 rng(17);
  const Cam cam = test::random_camera(70, 45, rng);
  const Scene g = test::random_scene(500, 3, false, rng);
  const ref::StyleMlp<float> mlp = test::random_mlp(g.size(), ref::StyleDepth::ndc, true, rng);
  test::DeviceScene dev(test::context(), g);
  test::DeviceStyle style(test::context(), mlp);
  style.attach(dev);
  splat::Rasterizer r(test::context());
  const test::GpuForward f = test::gpu_forward(r, dev, cam, kBg);
  const auto v = test::random_cotangents(cam, rng, true);
  const test::GpuBackward b = test::gpu_backward(r, dev, v, f.img.alpha.size());
  const auto tf = ref::render_style_fwd(g, mlp, cam, kBg);
  const auto tg = ref::render_style_bwd(g, mlp, cam, kBg, tf, v);
  // The projections agree to ~5e-7 and no sample sits within that of a cutoff in this scene, so
  // the differences are rounding: measured rgb 3.2e-7, MLP gradients 3.5e-7, quaternions 6.8e-7.
  test::expect_allclose(f.img.rgb, tf.img.rgb, {.of_largest = 1e-5}, "f.img.rgb");
  test::expect_allclose(f.img.alpha, tf.img.alpha, {.of_largest = 1e-5}, "f.img.alpha");
  test::expect_allclose(style.download_v_mlp(test::context()), tg.v_mlp, {.of_largest = 1e-5}, "v_mlp");
  test::expect_param_grads_allclose(b.grads, tg.g, false, {.of_largest = 1e-5});
}

// Half storage (docs/rasterizer.md): the style_raster_fwd*_half variants read each MLP weight with
// unpackHalf2x16, the half's exact value, so they render what the float variants render from the
// weights rounded to halves: the same bits, and the twin on the rounded weights within the float
// path's tolerances above (measured worst, lavapipe, Mesa 22.3.6: rgb 3.0e-7, alpha 1.8e-7). Both
// forward variants, both depth modes.
TEST_CASE("GPU style forward reading MLP weights stored as halves renders the float path's bits on half-rounded weights") {
  for (const auto& [depth, pixels] : {std::pair{ref::StyleDepth::ndc, 0u}, std::pair{ref::StyleDepth::relative, 1u}}) {
    CAPTURE(static_cast<int>(depth));
    CAPTURE(pixels);
    std::mt19937 rng(static_cast<unsigned>(400 + 2 * static_cast<int>(depth) + pixels));
    const Cam cam = test::random_camera(83, 61, rng);
    const Scene g = test::random_scene(700, 2, false, rng);
    ref::StyleMlp<float> mlp = test::random_mlp(g.size(), depth, true, rng);
    mlp.depth_scale = 1.0f / (3.0f * 0.05f);
    ref::StyleMlp<float> rounded = mlp;
    rounded.weights = test::rounded_to_half(mlp.weights);
    test::DeviceScene half(test::context(), g), full(test::context(), g);
    test::DeviceStyle style_half(test::context(), mlp), style_full(test::context(), rounded);
    style_half.store_as_halves(test::context(), mlp, half);
    style_full.attach(full);
    const test::GpuForward fh = test::expect_half_renders_as_float(test::context(), half, full, cam, kBg, pixels);

    const std::vector<float> quadric = ref::style_quadric(g, cam);
    const ref::Image<float> ti = ref::style_raster_fwd(fh.proj, quadric, rounded, cam, kBg);
    test::expect_allclose(fh.img.rgb, ti.rgb, {.atol = 1e-5}, "fh.img.rgb");
    test::expect_allclose(fh.img.alpha, ti.alpha, {.atol = 1e-5}, "fh.img.alpha");
    test::expect_equal_arrays(fh.img.count, ti.count, "contributors per pixel");
  }
}
