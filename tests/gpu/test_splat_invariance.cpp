// GPU rasterizer invariances (rerender, culled/transparent extras, input order, split dispatches,
// more than 65,535 workgroups), end-to-end agreement with the twin, and bad-input errors.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <stdexcept>
#include <utility>
#include <vector>

#include "expect_allclose.h"
#include "expect_equal.h"
#include "splat_harness.h"
#include "test_context.h"

namespace {

using namespace s4d;
using test::Cam;
using test::Scene;

constexpr std::array<float, 3> kBg = {0.2f, 0.2f, 0.25f};

ref::ImageGrads<float> cotangents(const Cam& cam, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1, 1);
  ref::ImageGrads<float> v;
  const size_t npix = static_cast<size_t>(cam.width * cam.height);
  for (size_t k = 0; k < 3 * npix; ++k) v.v_rgb.push_back(u(rng));
  for (size_t k = 0; k < npix; ++k) v.v_alpha.push_back(u(rng)), v.v_depth.push_back(0.1f * u(rng));
  return v;
}

// Appends Gaussian i of src to dst.
void append(Scene& dst, const Scene& src, size_t i) {
  auto copy = [&](std::vector<float>& d, const std::vector<float>& s, size_t width) {
    d.insert(d.end(), s.begin() + static_cast<long>(width * i), s.begin() + static_cast<long>(width * (i + 1)));
  };
  copy(dst.means, src.means, 3), copy(dst.log_scales, src.log_scales, 3), copy(dst.quats, src.quats, 4);
  copy(dst.opacity_logits, src.opacity_logits, 1), copy(dst.sh, src.sh, 3 * src.sh_coeffs());
  if (!src.colors.empty()) copy(dst.colors, src.colors, 3);
}

struct Rendered {
  test::GpuForward f;
  test::GpuBackward b;
};

Rendered render(engine::Context& ctx, const Scene& g, const Cam& cam, unsigned cot_seed = 5) {
  test::DeviceScene dev(ctx, g);
  splat::Rasterizer r(ctx);
  test::GpuForward f = test::gpu_forward(r, dev, cam, kBg);
  test::GpuBackward b = test::gpu_backward(r, dev, cotangents(cam, cot_seed), static_cast<size_t>(cam.width * cam.height));
  return {std::move(f), std::move(b)};
}

}  // namespace

TEST_CASE("GPU render and gradients match the twin end to end") {
  std::mt19937 rng(3);
  const Cam cam = test::random_camera(70, 45, rng);
  const Scene g = test::random_scene(800, 3, false, rng);
  const Rendered gpu = render(test::context(), g, cam);
  const auto [tp, ti] = ref::render_fwd(g, cam, kBg);
  const ref::GaussianGrads<float> tg = ref::render_bwd(g, cam, kBg, tp, ti, cotangents(cam, 5));
  // The two projections agree to 3e-7 (see test_splat_raster.cpp) and no sample sits within that
  // of a cutoff in this scene, so the end-to-end errors are rounding: measured rgb 1.8e-7, means 3.4e-7.
  test::expect_allclose(gpu.f.img.rgb, ti.rgb, {.of_largest = 1e-5}, "gpu.f.img.rgb");
  test::expect_allclose(gpu.f.img.alpha, ti.alpha, {.of_largest = 1e-5}, "gpu.f.img.alpha");
  test::expect_allclose(gpu.f.img.depth, ti.depth, {.of_largest = 1e-5}, "gpu.f.img.depth");
  test::expect_param_grads_allclose(gpu.b.grads, tg, false, {.of_largest = 1e-5});
  test::expect_allclose(gpu.b.grads.v_mean2d, tg.v_mean2d, {.of_largest = 1e-5}, "gpu.b.grads.v_mean2d");
}

TEST_CASE("rendering twice is bit-identical") {
  std::mt19937 rng(4);
  const Cam cam = test::random_camera(64, 48, rng);
  const Scene g = test::random_scene(1000, 2, false, rng);
  test::DeviceScene dev(test::context(), g);
  splat::Rasterizer r(test::context());
  const auto a = test::gpu_forward(r, dev, cam, kBg);
  const auto b = test::gpu_forward(r, dev, cam, kBg);
  CHECK(a.img.rgb == b.img.rgb);  // exact: projection, stable sorts and blending are deterministic
  CHECK(a.img.alpha == b.img.alpha);
  CHECK(a.img.depth == b.img.depth);
  CHECK(a.img.count == b.img.count);
  const auto v = cotangents(cam, 9);
  const auto ga = test::gpu_backward(r, dev, v, a.img.alpha.size());
  const auto gb = test::gpu_backward(r, dev, v, a.img.alpha.size());
  // Float atomics may sum in another order on other devices; lavapipe measured 0.
  test::expect_allclose(ga.grads.v_means, gb.grads.v_means, {.of_largest = 1e-6}, "ga.grads.v_means");
  test::expect_allclose(ga.grads.v_sh, gb.grads.v_sh, {.of_largest = 1e-6}, "ga.grads.v_sh");
}

TEST_CASE("culled and fully transparent Gaussians change nothing") {
  std::mt19937 rng(5);
  const Cam cam = test::random_camera(64, 48, rng);
  const Scene g = test::random_scene(600, 1, false, rng);
  Scene extra = g;
  for (size_t i = 0; i < 300; ++i) {
    append(extra, g, i);
    float* m = &extra.means[extra.means.size() - 3];
    switch (i % 3) {
      case 0: m[2] = -m[2]; break;                           // behind the camera
      case 1: m[0] = 500.0f * m[2]; break;                    // far outside the frustum: empty rectangle
      default: extra.opacity_logits.back() = -30.0f; break;   // alpha ~ 1e-13 < 1/255: skipped
    }
  }
  const Rendered base = render(test::context(), g, cam), more = render(test::context(), extra, cam);
  CHECK(more.f.img.rgb == base.f.img.rgb);  // exact: same samples blended in the same order
  CHECK(more.f.img.alpha == base.f.img.alpha);
  CHECK(more.f.img.depth == base.f.img.depth);
  CHECK(more.f.img.count == base.f.img.count);
  std::vector<float> head(more.b.grads.v_means.begin(), more.b.grads.v_means.begin() + 3 * 600);
  test::expect_allclose(head, base.b.grads.v_means, {.of_largest = 1e-6}, "head");  // only the atomics' order may differ; measured 0
  for (size_t i = 600; i < extra.size(); ++i) {
    for (size_t k = 0; k < 3; ++k) REQUIRE(more.b.grads.v_means[3 * i + k] == 0.0f);  // exact: never blended
    REQUIRE(more.b.grads.v_opacity_logits[i] == 0.0f);
  }
  for (size_t i = 600; i < extra.size(); i += 3) CHECK(more.f.proj.radius[i] == 0);
}

TEST_CASE("permuting the input order changes nothing beyond float reordering") {
  std::mt19937 rng(6);
  const Cam cam = test::random_camera(64, 48, rng);
  const Scene g = test::random_scene(700, 3, false, rng);
  std::vector<size_t> perm(g.size());
  std::iota(perm.begin(), perm.end(), size_t{0});
  std::shuffle(perm.begin(), perm.end(), rng);
  Scene h;
  h.sh_degree = g.sh_degree;
  for (size_t i : perm) append(h, g, i);
  const Rendered a = render(test::context(), g, cam), b = render(test::context(), h, cam);
  // Distinct depths give the same blend order: measured 0 difference; the bound allows reordering.
  test::expect_allclose(b.f.img.rgb, a.f.img.rgb, {.of_largest = 1e-6}, "b.f.img.rgb");
  test::expect_allclose(b.f.img.depth, a.f.img.depth, {.of_largest = 1e-6}, "b.f.img.depth");
  std::vector<float> permuted(3 * g.size());
  for (size_t j = 0; j < perm.size(); ++j)
    for (size_t k = 0; k < 3; ++k) permuted[3 * j + k] = a.b.grads.v_means[3 * perm[j] + k];
  test::expect_allclose(b.b.grads.v_means, permuted, {.of_largest = 1e-6}, "b.b.grads.v_means");
}

TEST_CASE("dispatches split into a 2-D grid render the same image") {
  engine::ContextOptions opts = engine::ContextOptions::from_env();
  opts.max_groups_x = 3;  // every dispatch of more than 3 workgroups takes the 2-D path
  engine::Context split_ctx(opts);
  std::mt19937 rng(7);
  const Cam cam = test::random_camera(100, 70, rng);  // 7 x 5 tiles
  const Scene g = test::random_scene(2000, 1, false, rng);
  const Rendered a = render(test::context(), g, cam), b = render(split_ctx, g, cam);
  CHECK(b.f.img.rgb == a.f.img.rgb);  // exact: the same work, only the grid shape differs
  CHECK(b.f.img.count == a.f.img.count);
  test::expect_allclose(b.b.grads.v_means, a.b.grads.v_means, {.of_largest = 1e-6}, "b.b.grads.v_means");  // atomics order only; measured 0
  test::expect_allclose(b.b.grads.v_quats, a.b.grads.v_quats, {.of_largest = 1e-6}, "b.b.grads.v_quats");
}

TEST_CASE("more than 65,535 workgroups of tile instances") {
  // 4100 opaque Gaussians that each cover all 64 x 64 tiles of a 1024^2 image: 16.8M instances,
  // so the instance kernels need 65,600 workgroups of 256 and the device grid splits.
  const uint32_t side = 1024;
  Cam cam;
  cam.world_to_cam = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  cam.fx = cam.fy = 800, cam.cx = cam.cy = side / 2.0f, cam.width = cam.height = static_cast<int>(side);
  std::mt19937 rng(8);
  std::uniform_real_distribution<float> u(-1, 1);
  Scene g;
  const size_t n = 4100;
  for (size_t i = 0; i < n; ++i) {
    const float z = 5.0f + 0.001f * static_cast<float>(i);
    for (float m : {0.01f * u(rng), 0.01f * u(rng), z}) g.means.push_back(m);
    for (int k = 0; k < 3; ++k) g.log_scales.push_back(std::log(4.0f));
    for (float q : {1.0f, 0.0f, 0.0f, 0.0f}) g.quats.push_back(q);
    g.opacity_logits.push_back(u(rng));
    for (int ch = 0; ch < 3; ++ch) g.sh.push_back(u(rng));
  }
  test::DeviceScene dev(test::context(), g);
  splat::Rasterizer r(test::context());
  const auto f = test::gpu_forward(r, dev, cam, kBg);
  REQUIRE(f.instances == n * 64 * 64);
  REQUIRE(f.instances > 65535u * 256u);
  // Blended on the GPU's own projection. Every pixel here blends until T < 1e-4, and where T lands
  // within rounding of that threshold one side adds one more Gaussian: a jump of alpha*T*colour
  // < 1e-4 * max colour. Measured 4.9e-5 (relative to the brightest pixel); elsewhere rounding only.
  const ref::Image<float> ti = ref::raster_fwd(f.proj, cam, kBg);
  test::expect_allclose(f.img.rgb, ti.rgb, {.of_largest = 2e-4}, "f.img.rgb");
  const auto b = test::gpu_backward(r, dev, cotangents(cam, 1), f.img.alpha.size());
  for (float x : b.grads.v_means) REQUIRE(std::isfinite(x));
}

TEST_CASE("bad rasterizer inputs are refused with a clear message") {
  std::mt19937 rng(9);
  const Scene g = test::random_scene(10, 1, false, rng);
  test::DeviceScene dev(test::context(), g);
  splat::Rasterizer r(test::context());
  const splat::Camera cam = test::gpu_camera(test::random_camera(32, 32, rng));
  splat::GaussianParams p = dev.params;
  p.sh_degree = 4;
  CHECK_THROWS_WITH_AS(r.forward(p, cam, kBg), doctest::Contains("sh_degree 4"), std::invalid_argument);
  p = dev.params;
  p.count = 11;  // one more than the buffers hold
  CHECK_THROWS_WITH_AS(r.forward(p, cam, kBg), doctest::Contains("'means'"), std::invalid_argument);
  splat::Camera empty = cam;
  empty.width = 0;
  CHECK_THROWS_WITH_AS(r.forward(dev.params, empty, kBg), doctest::Contains("empty"), std::invalid_argument);
  splat::Camera nan_pose = cam;
  nan_pose.world_to_cam[3] = std::nanf("");
  CHECK_THROWS_WITH_AS(r.forward(dev.params, nan_pose, kBg), doctest::Contains("not finite"), std::invalid_argument);
  splat::Rasterizer fresh(test::context());
  CHECK_THROWS_AS(fresh.backward(dev.params, {}, dev.grads), std::logic_error);
}
