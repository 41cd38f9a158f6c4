// The style kernels at lavapipe's tile-list limits (S4D_LLVMPIPE_MAX_STYLE_LIST{,_CAS} in
// s4d_style_splat.h): lists exactly that long render and differentiate every entry, so the limits
// are honest (llvmpipe would stop the loops silently, dropping the entries at the end), and the
// rasterizer refuses longer ones on lavapipe.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <tuple>
#include <utility>
#include <vector>

#include "style_harness.h"
#include "test_context.h"

namespace {

using namespace s4d;
using test::Cam;
using test::Scene;

constexpr std::array<float, 3> kBg = {0.3f, 0.3f, 0.3f};

// One 16x16 tile looking down +z, fx = fy = 16.
Cam tile_camera() {
  Cam cam;
  cam.world_to_cam = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  cam.fx = cam.fy = 16, cam.cx = cam.cy = 8, cam.width = cam.height = 16;
  return cam;
}

// Adds an isotropic Gaussian at pixel (u, v) and depth z with a pixel-space sigma and an opacity.
void add(Scene& g, const Cam& cam, float u, float v, float z, float sigma_px, float opacity, std::mt19937& rng) {
  std::uniform_real_distribution<float> u01(0, 1);
  for (float m : {(u - cam.cx) * z / cam.fx, (v - cam.cy) * z / cam.fy, z}) g.means.push_back(m);
  for (int k = 0; k < 3; ++k) g.log_scales.push_back(std::log(sigma_px * z / cam.fx));
  for (float q : {1.0f, 0.0f, 0.0f, 0.0f}) g.quats.push_back(q);
  g.opacity_logits.push_back(std::log(opacity / (1 - opacity)));
  for (int ch = 0; ch < 3; ++ch) g.sh.push_back(u01(rng));
}

}  // namespace

TEST_CASE("a tile list at the compare-and-swap limit differentiates every entry; longer ones are refused") {
  // Every pair contributes: wide Gaussians (G ~ 1 over the tile) at opacity 0.0075, and MLPs whose
  // opacity output row is scaled down so |dO| < 0.002: alpha in [0.0055, 0.0095], above the 1/255
  // cutoff and never ending a pixel early (0.9905^900 = 1.9e-4 > 1e-4). So the elected lane of every
  // subgroup runs all 62 compare-and-swap loops per entry, the worst case the limit assumes.
  const Cam cam = tile_camera();
  std::mt19937 rng(51);
  std::uniform_real_distribution<float> u(-1, 1);
  Scene g;
  const size_t n = S4D_LLVMPIPE_MAX_STYLE_LIST_CAS;
  for (size_t i = 0; i < n + 1; ++i) add(g, cam, 8 + 2 * u(rng), 8 + 2 * u(rng), 3 + u(rng), 100, 0.0075f, rng);
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
  CHECK(test::max_abs(f.img.rgb, ti.rgb) <= 1e-5);  // 900 blended terms in the same order; measured 1.8e-7
  std::mt19937 vrng(4);
  const auto v = test::random_cotangents(cam, vrng, false);
  const test::GpuBackward b = test::gpu_backward(r, dev, v, 256);
  const auto tg = ref::style_raster_bwd(f.proj, quadric, head_mlp, cam, kBg, ti, v);
  // T_i is recovered by up to 900 divisions by (1 - alpha); measured 2.1e-6 (MLP) and 1.2e-6 (opacity).
  CHECK(test::rel_err(style.download_v_mlp(test::context()), tg.v_mlp) <= 1e-4);
  CHECK(test::rel_err(b.grad2d.v_opacity, tg.g2d.v_opacity) <= 1e-4);
  CHECK(test::rel_err(b.grad2d.v_rgb, tg.g2d.v_rgb) <= 1e-4);

  if (test::context().info().driver_name == "llvmpipe") {
    test::DeviceScene longer(test::context(), g);
    test::DeviceStyle longer_style(test::context(), mlp);
    longer_style.attach(longer);
    test::gpu_forward(r, longer, cam, kBg);
    CHECK_THROWS_WITH_AS(test::gpu_backward(r, longer, v, 256), doctest::Contains("65535"), std::runtime_error);
  }
}

TEST_CASE("a tile list at the float-atomic limit renders and differentiates every entry") {
  // 32 Gaussians in front and 32 behind blend visibly (alpha ~0.05: no pixel ends early); in
  // between, fillers just right of the image whose 3-sigma rectangle still covers the tile but whose
  // G <= 0.0034 keeps (o + 0.5) G under 1/255, so every pixel skips them. If llvmpipe stopped the
  // loops early, the forward would lose the back ones and the backward (which walks back to front)
  // the front ones; the list without fillers is the reference.
  const Cam cam = tile_camera();
  std::mt19937 rng(52);
  std::uniform_real_distribution<float> u(-1, 1), u01(0, 1);
  const size_t n = S4D_LLVMPIPE_MAX_STYLE_LIST, visible = 64;
  Scene g, reference;
  for (size_t i = 0; i < visible; ++i) {
    const float z = i < visible / 2 ? 2 + 0.1f * u01(rng) : 10 + 0.1f * u01(rng);
    add(g, cam, 8 + 4 * u(rng), 8 + 4 * u(rng), z, 20, 0.05f, rng);
  }
  reference = g;
  for (size_t i = visible; i < n; ++i) add(g, cam, 18, 2 + 12 * u01(rng), 3 + 6 * u01(rng), 0.5f, 1e-4f, rng);
  const ref::StyleMlp<float> mlp = test::random_mlp(n, ref::StyleDepth::relative, false, rng);
  ref::StyleMlp<float> reference_mlp = mlp;
  reference_mlp.weights.resize(ref::kStyleMlpStride * visible);

  auto run = [&](const Scene& scene, const ref::StyleMlp<float>& weights) {
    test::DeviceScene dev(test::context(), scene);
    test::DeviceStyle style(test::context(), weights);
    style.attach(dev);
    splat::Rasterizer r(test::context());
    test::GpuForward f = test::gpu_forward(r, dev, cam, kBg);
    std::mt19937 vrng(6);
    test::GpuBackward b = test::gpu_backward(r, dev, test::random_cotangents(cam, vrng, true), 256);
    return std::tuple(std::move(f), std::move(b), style.download_v_mlp(test::context()));
  };
  const auto [f, b, v_mlp] = run(g, mlp);
  const auto [rf, rb, rv_mlp] = run(reference, reference_mlp);
  REQUIRE(f.longest_tile_list == n);
  CHECK(f.img.count == rf.img.count);  // exact: the fillers are skipped, the rest blend in the same order
  CHECK(f.img.rgb == rf.img.rgb);
  CHECK(*std::min_element(f.img.count.begin(), f.img.count.end()) == static_cast<int>(visible));
  std::vector<float> head(v_mlp.begin(), v_mlp.begin() + static_cast<long>(reference_mlp.weights.size()));
  CHECK(test::rel_err(head, rv_mlp) <= 1e-6);  // the same subgroup sums in the same order; measured 0
  std::vector<float> means(b.grads.v_means.begin(), b.grads.v_means.begin() + 3 * visible);
  CHECK(test::rel_err(means, rb.grads.v_means) <= 1e-6);  // measured 0
  for (size_t k = head.size(); k < v_mlp.size(); ++k) REQUIRE(v_mlp[k] == 0.0f);  // fillers never blend
}
