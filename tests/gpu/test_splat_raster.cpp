// The GPU rasterizer against its CPU twin on lavapipe: projection, blending and both backward
// kernels, stage by stage (the twin fed the GPU's own intermediates, so tile lists are identical)
// and end to end, for SH degrees 0..3, the colour override and the compare-and-swap atomics path.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <tuple>
#include <vector>

#include "expect_allclose.h"
#include "expect_equal.h"
#include "splat_harness.h"
#include "test_context.h"

namespace {

using namespace s4d;
using test::Cam;
using test::Scene;

constexpr std::array<float, 3> kBg = {0.1f, 0.3f, 0.6f};

ref::ImageGrads<float> random_cotangents(const Cam& cam, std::mt19937& rng, bool alpha_depth) {
  std::uniform_real_distribution<float> u(-1, 1);
  ref::ImageGrads<float> v;
  const size_t npix = static_cast<size_t>(cam.width * cam.height);
  for (size_t k = 0; k < 3 * npix; ++k) v.v_rgb.push_back(u(rng));
  if (alpha_depth)
    for (size_t k = 0; k < npix; ++k) v.v_alpha.push_back(u(rng)), v.v_depth.push_back(0.1f * u(rng));
  return v;
}

struct Case {
  int sh_degree;
  bool colors;
  bool cas;           // compare-and-swap atomics instead of float atomics
  bool alpha_depth;   // cotangents on the alpha and depth outputs too
  uint32_t pixels = 0;  // pixels per invocation, forward and backward: 0 by device (8 on lavapipe), or the GPUs' 1
};

}  // namespace

// Tolerances below: the GPU and the twin evaluate the same float formulas; exp/sqrt/division differ
// in the last bits and the atomics sum in another order. Measured worst cases over the six cases
// (lavapipe, Mesa 22.3.6): projection 2.9e-7, blending 2.4e-7, grad2d 8.0e-7, parameters 7.1e-7;
// 1e-5 leaves a 12x margin and still catches any wrong term (those are O(1) relative errors).
TEST_CASE("GPU projection, blending and backward match the twin stage by stage") {
  for (const Case c : {Case{0, false, false, true}, Case{1, false, false, false}, Case{2, false, true, true},
                       Case{3, false, false, true}, Case{3, true, false, true}, Case{1, true, true, false},
                       Case{3, false, false, true, 1}, Case{2, true, true, true, 1}}) {
    CAPTURE(c.sh_degree);
    CAPTURE(c.colors);
    CAPTURE(c.cas);
    CAPTURE(c.pixels);
    std::mt19937 rng(static_cast<unsigned>(100 + c.sh_degree * 7 + c.colors * 3 + c.cas + 11 * c.pixels));
    const Cam cam = test::random_camera(83, 61, rng);  // not multiples of 16: partial tiles
    const Scene g = test::random_scene(1500, c.sh_degree, c.colors, rng);
    test::DeviceScene dev(test::context(), g);
    splat::Rasterizer r(test::context(), "raster", {.force_cas_atomics = c.cas, .backward_pixels = c.pixels, .forward_pixels = c.pixels});
    const test::GpuForward f = test::gpu_forward(r, dev, cam, kBg);

    const ref::Projected<float> tp = ref::project_fwd(g, cam);
    test::expect_equal_arrays(f.proj.radius, tp.radius, "radius");
    test::expect_equal_arrays(f.proj.tile_rect, tp.tile_rect, "tile rectangles");
    test::expect_equal_arrays(f.proj.clamped, tp.clamped, "SH clamp bits");
    test::expect_allclose(f.proj.mean2d, tp.mean2d, {.of_largest = 1e-5}, "f.proj.mean2d");
    test::expect_allclose(f.proj.conic, tp.conic, {.of_largest = 1e-5}, "f.proj.conic");
    test::expect_allclose(f.proj.depth, tp.depth, {.of_largest = 1e-5}, "f.proj.depth");
    test::expect_allclose(f.proj.opacity, tp.opacity, {.atol = 1e-5}, "f.proj.opacity");
    test::expect_allclose(f.proj.rgb, tp.rgb, {.atol = 1e-5}, "f.proj.rgb");

    // Blending on the GPU's own projection, so the tile lists are identical.
    const ref::Image<float> ti = ref::raster_fwd(f.proj, cam, kBg);
    test::expect_allclose(f.img.rgb, ti.rgb, {.atol = 1e-5}, "f.img.rgb");
    test::expect_allclose(f.img.alpha, ti.alpha, {.atol = 1e-5}, "f.img.alpha");
    test::expect_allclose(f.img.depth, ti.depth, {.of_largest = 1e-5}, "f.img.depth");
    test::expect_equal_arrays(f.img.count, ti.count, "contributors per pixel");
    size_t instances = 0;
    for (const auto& list : ref::tile_lists(f.proj, cam)) instances += list.size();
    CHECK(f.instances == instances);

    // Raster backward on the same lists, then the preprocess backward on the GPU's grad2d.
    const auto v = random_cotangents(cam, rng, c.alpha_depth);
    const test::GpuBackward b = test::gpu_backward(r, dev, v, ti.alpha.size());
    const ref::ProjectedGrads<float> tg2 = ref::raster_bwd(f.proj, cam, kBg, ti, v);
    test::expect_allclose(b.grad2d.v_mean2d, tg2.v_mean2d, {.of_largest = 1e-5}, "b.grad2d.v_mean2d");
    test::expect_allclose(b.grad2d.v_conic, tg2.v_conic, {.of_largest = 1e-5}, "b.grad2d.v_conic");
    test::expect_allclose(b.grad2d.v_opacity, tg2.v_opacity, {.of_largest = 1e-5}, "b.grad2d.v_opacity");
    test::expect_allclose(b.grad2d.v_rgb, tg2.v_rgb, {.of_largest = 1e-5}, "b.grad2d.v_rgb");
    test::expect_allclose(b.grad2d.v_depth, tg2.v_depth, {.of_largest = 1e-5}, "b.grad2d.v_depth");
    const ref::GaussianGrads<float> tg = ref::project_bwd(g, cam, f.proj, b.grad2d);
    test::expect_param_grads_allclose(b.grads, tg, c.colors, {.of_largest = 1e-5});
  }
}

// Half storage (docs/rasterizer.md): project_fwd_half reads each SH coefficient with
// unpackHalf2x16, which gives the half's exact value, so it renders what project_fwd renders from
// the SH rounded to halves: the same bits in both forward variants, and the twin on the rounded SH
// within the float path's tolerances above (measured worst, lavapipe, Mesa 22.3.6: projected colour
// 0, image and alpha 1.8e-7). K = 1 stores 3 halves a Gaussian, so Gaussians share words; K = 16
// (degree 3) 48.
TEST_CASE("GPU projection reading SH stored as halves renders the float path's bits on half-rounded SH") {
  for (const auto& [sh_degree, coeffs, pixels] : {std::tuple{0, 1, 0u}, std::tuple{3, 16, 0u}, std::tuple{3, 16, 1u}}) {
    CAPTURE(sh_degree);
    CAPTURE(pixels);
    std::mt19937 rng(static_cast<unsigned>(300 + sh_degree + pixels));
    const Cam cam = test::random_camera(83, 61, rng);
    Scene g = test::random_scene(1501, sh_degree, false, rng);
    if (coeffs == 1) {  // random_scene stores 16 coefficients; keep each Gaussian's first
      std::vector<float> dc(3 * g.size());
      for (size_t j = 0; j < dc.size(); ++j) dc[j] = g.sh[16 * 3 * (j / 3) + j % 3];
      g.sh = dc;
    }
    Scene rounded = g;
    rounded.sh = test::rounded_to_half(g.sh);
    test::DeviceScene half(test::context(), g), full(test::context(), rounded);
    test::store_sh_as_halves(test::context(), half, g);
    const test::GpuForward fh = test::expect_half_renders_as_float(test::context(), half, full, cam, kBg, pixels);

    const ref::Projected<float> tp = ref::project_fwd(rounded, cam);
    test::expect_equal_arrays(fh.proj.clamped, tp.clamped, "SH clamp bits");
    test::expect_allclose(fh.proj.rgb, tp.rgb, {.atol = 1e-5}, "fh.proj.rgb");
    const ref::Image<float> ti = ref::raster_fwd(fh.proj, cam, kBg);
    test::expect_allclose(fh.img.rgb, ti.rgb, {.atol = 1e-5}, "fh.img.rgb");
    test::expect_allclose(fh.img.alpha, ti.alpha, {.atol = 1e-5}, "fh.img.alpha");

    splat::Rasterizer r(test::context());
    r.forward(half.params, test::gpu_camera(cam), kBg);
    const auto v = random_cotangents(cam, rng, false);
    CHECK_THROWS_WITH_AS(test::gpu_backward(r, half, v, ti.alpha.size()),
                         "rasterizer: backward() needs float sh and style_mlp; half storage renders only",
                         std::invalid_argument);
  }
}
