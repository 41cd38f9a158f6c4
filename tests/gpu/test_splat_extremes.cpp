// The GPU rasterizer at the extremes: every output and gradient stays finite, and
// each case's documented behaviour holds.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "expect_allclose.h"
#include "expect_equal.h"
#include "s4d/splat/scene_upload.h"
#include "splat_harness.h"
#include "test_context.h"

namespace {

using namespace s4d;
using test::Cam;
using test::Scene;

constexpr std::array<float, 3> kBg = {0.3f, 0.3f, 0.3f};

Cam straight_camera(int width, int height) {
  Cam cam;
  cam.world_to_cam = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  cam.fx = cam.fy = static_cast<float>(std::max(width, height));
  cam.cx = 0.5f * static_cast<float>(width), cam.cy = 0.5f * static_cast<float>(height);
  cam.width = width, cam.height = height;
  return cam;
}

// A few ordinary Gaussians (scene size ~1 at depth ~3) plus one extreme one appended last.
Scene base_scene() {
  std::mt19937 rng(21);
  Scene g = test::random_scene(20, 3, false, rng);
  for (size_t i = 0; i < g.size(); ++i) g.means[3 * i + 2] = 3.0f + 0.1f * static_cast<float>(i);
  return g;
}

Scene with_extreme(float x, float y, float z, std::array<float, 3> log_scales, std::array<float, 4> quat,
                   float opacity_logit) {
  Scene g = base_scene();
  for (float m : {x, y, z}) g.means.push_back(m);
  for (float s : log_scales) g.log_scales.push_back(s);
  for (float q : quat) g.quats.push_back(q);
  g.opacity_logits.push_back(opacity_logit);
  for (int k = 0; k < 16; ++k)
    for (int ch = 0; ch < 3; ++ch) g.sh.push_back(k == 0 ? 0.8f : 0.1f);
  return g;
}

struct Result {
  test::GpuForward f;
  test::GpuBackward b;
};

bool finite(const std::vector<float>& v) {
  return std::all_of(v.begin(), v.end(), [](float x) { return std::isfinite(x); });
}

Result run(const Scene& g, const Cam& cam) {
  test::DeviceScene dev(test::context(), g);
  splat::Rasterizer r(test::context());
  Result out{test::gpu_forward(r, dev, cam, kBg), test::GpuBackward{}};
  std::mt19937 rng(2);
  std::uniform_real_distribution<float> u(-1, 1);
  ref::ImageGrads<float> v;
  const size_t npix = static_cast<size_t>(cam.width * cam.height);
  for (size_t k = 0; k < 3 * npix; ++k) v.v_rgb.push_back(u(rng));
  for (size_t k = 0; k < npix; ++k) v.v_alpha.push_back(u(rng)), v.v_depth.push_back(u(rng));
  out.b = test::gpu_backward(r, dev, v, npix);
  CHECK(finite(out.f.img.rgb));
  CHECK(finite(out.f.img.alpha));
  CHECK(finite(out.f.img.depth));
  CHECK(finite(out.b.grads.v_means));
  CHECK(finite(out.b.grads.v_log_scales));
  CHECK(finite(out.b.grads.v_quats));
  CHECK(finite(out.b.grads.v_opacity_logits));
  CHECK(finite(out.b.grads.v_sh));
  CHECK(finite(out.b.grads.v_mean2d));
  return out;
}

constexpr std::array<float, 4> kIdentity = {1, 0, 0, 0};
const float kLogUnit = std::log(0.3f);  // scene-sized Gaussian
const Cam kCam = straight_camera(40, 30);

}  // namespace

TEST_CASE("scales from 1e-6 to 1e4 of the scene size render finitely") {
  // 1e-6: the 0.3 px^2 dilation gives it a one-pixel footprint (radius >= 1), so it stays visible.
  const float tiny = std::log(0.3f * 1e-6f), huge = std::log(0.3f * 1e4f);
  const Result t = run(with_extreme(0.1f, 0.1f, 3, {tiny, tiny, tiny}, kIdentity, 2), kCam);
  CHECK(t.f.proj.radius.back() >= 1);
  // 1e4: its rectangle covers the whole image.
  const Result h = run(with_extreme(0.1f, 0.1f, 3, {huge, huge, huge}, kIdentity, 2), kCam);
  CHECK(h.f.proj.tile_rect[h.f.proj.tile_rect.size() - 4] == 0);
  CHECK(h.f.proj.tile_rect.back() == 2);
}

TEST_CASE("opacities 1e-6 and 1 - 1e-6") {
  const float lo = std::log(1e-6f / (1 - 1e-6f)), hi = -lo;
  const Scene base = base_scene();
  const Result none = run(base, kCam);
  // alpha <= 1e-6 < 1/255 everywhere: skipped, so the image is exactly the image without it.
  const Result faint = run(with_extreme(0, 0, 1.5f, {kLogUnit, kLogUnit, kLogUnit}, kIdentity, lo), kCam);
  CHECK(faint.f.img.rgb == none.f.img.rgb);
  CHECK(faint.b.grads.v_opacity_logits.back() == 0.0f);
  // alpha capped at 0.99 in front of everything: background and the rest show through at most 1%.
  const Result opaque = run(with_extreme(0, 0, 1.5f, {kLogUnit, kLogUnit, kLogUnit}, kIdentity, hi), kCam);
  const size_t centre = static_cast<size_t>(15 * 40 + 20);
  CHECK(opaque.f.img.alpha[centre] >= 0.99f - 1e-6f);
}

TEST_CASE("Gaussians behind the camera, on the near plane and at 1e6 depth") {
  const std::array<float, 3> s = {kLogUnit, kLogUnit, kLogUnit};
  const Result behind = run(with_extreme(0, 0, -2, s, kIdentity, 2), kCam);
  CHECK(behind.f.proj.radius.back() == 0);  // culled: z <= 0.2
  CHECK(behind.b.grads.v_means.back() == 0.0f);
  const Result on_plane = run(with_extreme(0, 0, 0.2f, s, kIdentity, 2), kCam);
  CHECK(on_plane.f.proj.radius.back() == 0);  // exactly z = 0.2: culled (the rule is z <= 0.2)
  const Result just_in = run(with_extreme(0, 0, 0.2001f, s, kIdentity, 2), kCam);
  CHECK(just_in.f.proj.radius.back() > 0);  // fills the view; the guard band keeps the Jacobian bounded
  const Result far = run(with_extreme(1e3f, 0, 1e6f, s, kIdentity, 2), kCam);
  CHECK(far.f.proj.radius.back() >= 1);  // a dilated sub-pixel dot
  CHECK(far.f.proj.depth.back() == doctest::Approx(1e6f));
}

TEST_CASE("needle and flat covariances") {
  const float thin = std::log(1e-4f), wide = std::log(1.0f);
  run(with_extreme(0, 0, 3, {thin, thin, wide}, {0.9f, 0.3f, 0.2f, 0.1f}, 2), kCam);  // needle, tilted
  run(with_extreme(0, 0, 3, {wide, wide, thin}, {0.7f, -0.2f, 0.5f, 0.3f}, 2), kCam);  // flat disc, tilted
  run(with_extreme(0, 0, 3, {wide, wide, thin}, kIdentity, 2), kCam);                  // disc facing the camera
  run(with_extreme(0, 0, 3, {wide, thin, wide}, kIdentity, 2), kCam);                  // disc seen edge-on
}

TEST_CASE("quaternions of near-zero length") {
  const std::array<float, 3> s = {kLogUnit, std::log(0.1f), kLogUnit};
  // Normalised after dividing by the largest component: 1e-20 * (1, 2, 3, 4) renders like (1, 2, 3, 4).
  const Result tiny = run(with_extreme(0, 0, 3, s, {1e-20f, 2e-20f, 3e-20f, 4e-20f}, 2), kCam);
  const Result unit = run(with_extreme(0, 0, 3, s, {1, 2, 3, 4}, 2), kCam);
  CHECK(tiny.f.img.rgb == unit.f.img.rgb);
  // All zero: identity rotation, and no gradient, since the rotation does not depend on it.
  const Result zero = run(with_extreme(0, 0, 3, s, {0, 0, 0, 0}, 2), kCam);
  const Result identity = run(with_extreme(0, 0, 3, s, kIdentity, 2), kCam);
  CHECK(zero.f.img.rgb == identity.f.img.rgb);
  for (size_t k = zero.b.grads.v_quats.size() - 4; k < zero.b.grads.v_quats.size(); ++k)
    CHECK(zero.b.grads.v_quats[k] == 0.0f);
}

TEST_CASE("100,000 Gaussians covering one tile") {
  // One 16x16 tile; 800 wide Gaussians at alpha 0.0086..0.009 (twice the 1/255 cutoff everywhere)
  // and the rest at alpha <= 1e-4 (skipped, far from the cutoff), so no sample sits near a
  // threshold, no pixel reaches T < 1e-4 (0.991^800 = 7e-4) and every pixel walks all 391 batches
  // forward and backward.
  const Cam cam = straight_camera(16, 16);
  std::mt19937 rng(31);
  std::uniform_real_distribution<float> u(-1, 1);
  Scene g;
  const size_t n = 100000;
  for (size_t i = 0; i < n; ++i) {
    for (float m : {0.3f * u(rng), 0.3f * u(rng), 3.0f + u(rng)}) g.means.push_back(m);
    for (int k = 0; k < 3; ++k) g.log_scales.push_back(std::log(8.0f));
    for (float q : kIdentity) g.quats.push_back(q);
    g.opacity_logits.push_back(i % 125 == 0 ? std::log(0.009f / 0.991f) : std::log(1e-4f / (1 - 1e-4f)));
    for (int ch = 0; ch < 3; ++ch) g.sh.push_back(u(rng));
  }
  test::DeviceScene dev(test::context(), g);
  splat::Rasterizer r(test::context());
  const test::GpuForward f = test::gpu_forward(r, dev, cam, kBg);
  CHECK(f.instances == n);
  CHECK(f.longest_tile_list == n);
  const ref::Image<float> ti = ref::raster_fwd(f.proj, cam, kBg);
  test::expect_allclose(f.img.rgb, ti.rgb, {.atol = 1e-5}, "rgb");  // 800 blended terms summed in the same order; measured 1.8e-7
  CHECK(*std::min_element(f.img.count.begin(), f.img.count.end()) == 800);

  std::mt19937 vrng(4);
  ref::ImageGrads<float> v;
  for (size_t k = 0; k < 3 * 256; ++k) v.v_rgb.push_back(u(vrng));
  const test::GpuBackward b = test::gpu_backward(r, dev, v, 256);
  const ref::ProjectedGrads<float> tg = ref::raster_bwd(f.proj, cam, kBg, ti, v);
  // T_i recovered by 800 divisions by (1 - alpha); measured 8.2e-7 of the largest value.
  test::expect_allclose(b.grad2d.v_opacity, tg.v_opacity, {.of_largest = 1e-4}, "v_opacity");
  for (float x : b.grads.v_means) REQUIRE(std::isfinite(x));

  if (test::context().info().driver_name == "llvmpipe") {
    // The compare-and-swap path loops per atomic, so lavapipe refuses this list instead of
    // silently truncating it.
    splat::Rasterizer cas(test::context(), "cas", {.force_cas_atomics = true});
    test::gpu_forward(cas, dev, cam, kBg);
    CHECK_THROWS_WITH_AS(test::gpu_backward(cas, dev, v, 256), doctest::Contains("65535"), std::runtime_error);
  }
}

TEST_CASE("images of 1x1 and of sizes that are not multiples of 16") {
  for (const auto& [w, h] : {std::pair{1, 1}, std::pair{17, 33}, std::pair{31, 1}}) {
    CAPTURE(w);
    CAPTURE(h);
    const Cam cam = straight_camera(w, h);
    const Scene g = base_scene();
    const Result r = run(g, cam);
    const ref::Image<float> ti = ref::raster_fwd(r.f.proj, cam, kBg);
    test::expect_allclose(r.f.img.rgb, ti.rgb, {.atol = 1e-5}, "rgb");  // rounding only, as in the stage tests
  }
}

TEST_CASE("long tile lists that terminate partway through a later batch, forward and backward") {
  // 2000 wide Gaussians over a 48x40 image (3x3 tiles) at alpha ~0.03: T drops below 1e-4 after
  // ~300 of them, inside the second batch of 256, at a different entry for each pixel.
  const Cam cam = straight_camera(48, 40);
  std::mt19937 rng(41);
  std::uniform_real_distribution<float> u(-1, 1);
  Scene g;
  g.sh_degree = 0;
  for (size_t i = 0; i < 2000; ++i) {
    for (float m : {0.2f * u(rng), 0.2f * u(rng), 3.0f + u(rng)}) g.means.push_back(m);
    for (int k = 0; k < 3; ++k) g.log_scales.push_back(std::log(6.0f) + 0.1f * u(rng));
    for (float q : kIdentity) g.quats.push_back(q);
    g.opacity_logits.push_back(std::log(0.03f / 0.97f) + 0.2f * u(rng));
    for (int ch = 0; ch < 3; ++ch) g.sh.push_back(u(rng));
  }
  const Result r = run(g, cam);
  CHECK(r.f.longest_tile_list == 2000);
  CHECK(*std::max_element(r.f.img.count.begin(), r.f.img.count.end()) > 256);
  CHECK(*std::max_element(r.f.img.count.begin(), r.f.img.count.end()) < 2000);
  const ref::Image<float> ti = ref::raster_fwd(r.f.proj, cam, kBg);
  test::expect_equal_arrays(r.f.img.count, ti.count, "contributors");

  std::mt19937 vrng(2);  // the cotangents run() used
  std::uniform_real_distribution<float> uv(-1, 1);
  ref::ImageGrads<float> v;
  for (size_t k = 0; k < 3 * 48 * 40; ++k) v.v_rgb.push_back(uv(vrng));
  for (size_t k = 0; k < 48 * 40; ++k) v.v_alpha.push_back(uv(vrng)), v.v_depth.push_back(uv(vrng));
  const ref::ProjectedGrads<float> tg = ref::raster_bwd(r.f.proj, cam, kBg, ti, v);
  // T_i is recovered by ~300 divisions by (1 - alpha) on the GPU and stored exactly by the twin:
  // measured up to 5.4e-6 relative to the largest entry.
  test::expect_allclose(r.b.grad2d.v_mean2d, tg.v_mean2d, {.of_largest = 1e-4}, "v_mean2d");
  test::expect_allclose(r.b.grad2d.v_conic, tg.v_conic, {.of_largest = 1e-4}, "v_conic");
  test::expect_allclose(r.b.grad2d.v_opacity, tg.v_opacity, {.of_largest = 1e-4}, "v_opacity");
  test::expect_allclose(r.b.grad2d.v_rgb, tg.v_rgb, {.of_largest = 1e-4}, "v_rgb");
  test::expect_allclose(r.b.grad2d.v_depth, tg.v_depth, {.of_largest = 1e-4}, "v_depth");
}

TEST_CASE("half storage refuses a finite value beyond half's range, naming the buffer, the index and the value") {
  CHECK_THROWS_WITH_AS(splat::upload_as(test::context(), "run sh", std::vector<float>{1.0f, -65520.0f}, splat::Storage::f16),
                       "run sh: value -65520.000000 at index 1 is beyond half precision's range (65504); render it in "
                       "float (without --half)",
                       std::invalid_argument);
  // The largest values that round to 65504 pack; three halves take two words.
  const engine::Buffer ok =
      splat::upload_as(test::context(), "run sh", std::vector<float>{65504.0f, -65519.0f, 1.0f}, splat::Storage::f16);
  CHECK(ok.size() == 8);
  CHECK(test::context().download<uint32_t>(ok, 2) == std::vector<uint32_t>{0xfbff7bffu, 0x00003c00u});
}
