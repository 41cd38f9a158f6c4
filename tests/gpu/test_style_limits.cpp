// The style backward at lavapipe's compare-and-swap tile-list limit (S4D_LLVMPIPE_MAX_STYLE_LIST_CAS
// in s4d_style_splat.h): a list that long differentiates every entry, so the limit is honest
// (llvmpipe would stop the loops silently), and the rasterizer refuses a longer one on lavapipe.
// The float-atomic limit is tested in test_style_long_list.cpp (slow).
#include <doctest/doctest.h>

#include <algorithm>
#include <random>
#include <stdexcept>
#include <vector>

#include "expect_allclose.h"
#include "style_harness.h"
#include "test_context.h"

namespace {

using namespace s4d;
using test::Cam;
using test::Scene;

constexpr std::array<float, 3> kBg = {0.3f, 0.3f, 0.3f};

}  // namespace

TEST_CASE("a tile list at the compare-and-swap limit differentiates every entry; longer ones are refused") {
  // Every pair contributes: wide Gaussians (G ~ 1 over the tile) at opacity 0.0075, and MLPs whose
  // opacity output row is scaled down so |dO| < 0.002: alpha in [0.0055, 0.0095], above the 1/255
  // cutoff and never ending a pixel early (0.9905^900 = 1.9e-4 > 1e-4). So the elected lane of every
  // subgroup runs all 62 compare-and-swap loops per entry, the worst case the limit assumes.
  const Cam cam = test::tile_camera();
  std::mt19937 rng(51);
  std::uniform_real_distribution<float> u(-1, 1);
  Scene g;
  const size_t n = S4D_LLVMPIPE_MAX_STYLE_LIST_CAS;
  for (size_t i = 0; i < n + 1; ++i)
    test::add_gaussian(g, cam, 8 + 2 * u(rng), 8 + 2 * u(rng), 3 + u(rng), 100, 0.0075f, rng);
  ref::StyleMlp<float> mlp = test::random_mlp(n + 1, ref::StyleDepth::ndc, true, rng);
  for (size_t i = 0; i < n + 1; ++i)
    for (size_t c = 0; c < 5; ++c) mlp.weights[ref::kStyleMlpStride * i + S4D_STYLE_MLP_W3 + 4 * c + 3] *= 0.002f;

  Scene head = g;
  head.means.resize(3 * n), head.log_scales.resize(3 * n), head.quats.resize(4 * n);
  head.opacity_logits.resize(n), head.sh.resize(3 * n);
  ref::StyleMlp<float> head_mlp = mlp;
  head_mlp.weights.resize(ref::kStyleMlpStride * n);
  test::DeviceScene dev(test::context(), head);
  test::DeviceStyle style(test::context(), head_mlp);
  style.attach(dev);
  splat::Rasterizer r(test::context(), "cas", {.force_cas_atomics = true});
  const test::GpuForward f = test::gpu_forward(r, dev, cam, kBg);
  REQUIRE(f.longest_tile_list == n);
  CHECK(*std::min_element(f.img.count.begin(), f.img.count.end()) == static_cast<int>(n));
  const std::vector<float> quadric = test::context().download<float>(r.quadric(), ref::kStyleQuadricStride * n);
  const ref::Image<float> ti = ref::style_raster_fwd(f.proj, quadric, head_mlp, cam, kBg);
  test::expect_allclose(f.img.rgb, ti.rgb, {.atol = 1e-5}, "f.img.rgb");  // 900 blended terms in the same order; measured 6.0e-7
  std::mt19937 vrng(4);
  const auto v = test::random_cotangents(cam, vrng, false);
  const test::GpuBackward b = test::gpu_backward(r, dev, v, 256);
  const auto tg = ref::style_raster_bwd(f.proj, quadric, head_mlp, cam, kBg, ti, v);
  // T_i is recovered by up to 900 divisions by (1 - alpha): measured 1.2e-6 (MLP), 7.2e-7 (opacity),
  // 8.5e-6 (colour).
  test::expect_allclose(style.download_v_mlp(test::context()), tg.v_mlp, {.of_largest = 1e-4}, "v_mlp");
  test::expect_allclose(b.grad2d.v_opacity, tg.g2d.v_opacity, {.of_largest = 1e-4}, "b.grad2d.v_opacity");
  test::expect_allclose(b.grad2d.v_rgb, tg.g2d.v_rgb, {.of_largest = 1e-4}, "b.grad2d.v_rgb");

  if (test::context().info().driver_name == "llvmpipe") {
    test::DeviceScene longer(test::context(), g);
    test::DeviceStyle longer_style(test::context(), mlp);
    longer_style.attach(longer);
    test::gpu_forward(r, longer, cam, kBg);
    CHECK_THROWS_WITH_AS(test::gpu_backward(r, longer, v, 256), doctest::Contains("65535"), std::runtime_error);
  }
}
