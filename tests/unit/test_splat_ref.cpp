// The splat CPU twin (training/ref/include/s4d/ref/splat_{project,raster}_ref.h): backward against
// central finite differences in double on the smooth-cutoff variant, float vs double forward,
// invariances, and finite outputs on hard inputs.
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <functional>
#include <random>
#include <string>
#include <type_traits>
#include <vector>

#include "expect_allclose.h"
#include "fd_check.h"
#include "s4d/ref/splat_raster_ref.h"

namespace {

using s4d::test::FdChecker;
using s4d::test::quat_tangents;
using s4d::ref::Camera;
using s4d::ref::Cutoff;
using s4d::ref::Gaussians;
using s4d::ref::Image;
using s4d::ref::ImageGrads;
using s4d::ref::Projected;

constexpr std::array<double, 3> kBackground = {0.2, 0.4, 0.6};

// 24x20 (not a multiple of 16: 2x2 tiles, partial tiles on the right and bottom). A small camera
// rotation and translation so the world->camera rotation W is exercised.
Camera<double> test_camera(int width = 24, int height = 20) {
  Camera<double> cam;
  const double ang = 0.1, c = std::cos(ang), s = std::sin(ang);
  cam.world_to_cam = {c, 0, s, 0.1, 0, 1, 0, -0.05, -s, 0, c, 0.3, 0, 0, 0, 1};
  cam.fx = 22, cam.fy = 21, cam.cx = width / 2.0 + 0.3, cam.cy = height / 2.0 - 0.2;
  cam.width = width, cam.height = height;
  return cam;
}

// Six Gaussians in front of the camera with distinct depths, large enough that every tile
// rectangle covers the whole image (no tile-culling discontinuity), colours well above the SH clamp.
Gaussians<double> test_scene(int sh_degree, bool color_override) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  Gaussians<double> g;
  g.sh_degree = sh_degree;
  const int n = 6, K = 16;
  for (int i = 0; i < n; ++i) {
    const double z = 3.0 + 0.37 * i;
    for (double m : {0.25 * u(rng) * z / 3, 0.25 * u(rng) * z / 3, z}) g.means.push_back(m);
    for (int k = 0; k < 3; ++k) g.log_scales.push_back(std::log(0.9 + 0.2 * u(rng)));
    for (int k = 0; k < 4; ++k) g.quats.push_back((k == 0 ? 1.2 : 0.0) + 0.5 * u(rng));  // norm != 1 on purpose
    g.opacity_logits.push_back(0.3 * u(rng));
    for (int k = 0; k < K; ++k)
      for (int ch = 0; ch < 3; ++ch) g.sh.push_back(k == 0 ? 0.4 + 0.2 * u(rng) : 0.05 * u(rng));
    if (color_override)
      for (int ch = 0; ch < 3; ++ch) g.colors.push_back(0.5 + 0.4 * u(rng));
  }
  return g;
}

// Random per-pixel weights (fixed seed): the cotangents of the weighted-sum loss.
ImageGrads<double> test_weights(int npix) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  ImageGrads<double> w;
  for (int p = 0; p < npix; ++p) {
    for (int ch = 0; ch < 3; ++ch) w.v_rgb.push_back(u(rng));
    w.v_alpha.push_back(u(rng));
    w.v_depth.push_back(0.3 * u(rng));
  }
  return w;
}

double weighted_loss(const Image<double>& img, const ImageGrads<double>& w) {
  double loss = 0;
  for (size_t k = 0; k < img.rgb.size(); ++k) loss += w.v_rgb[k] * img.rgb[k];
  for (size_t k = 0; k < img.alpha.size(); ++k) loss += w.v_alpha[k] * img.alpha[k] + w.v_depth[k] * img.depth[k];
  return loss;
}

template <class T>
bool all_finite(const std::vector<T>& v) {
  return std::all_of(v.begin(), v.end(), [](T x) { return std::isfinite(x); });
}

// Runs the full FD check of render_bwd on one scene. The hard variant is only piecewise smooth; it
// is checked on a scene where no pixel sits within the FD step of a threshold.
template <Cutoff kCutoff = Cutoff::smooth>
FdChecker check_render_gradients(Gaussians<double> g) {
  const Camera<double> cam = test_camera();
  const ImageGrads<double> w = test_weights(cam.width * cam.height);
  const auto [proj, img] = s4d::ref::render_fwd<kCutoff>(g, cam, kBackground);
  for (size_t i = 0; i < g.size(); ++i) {
    REQUIRE(proj.radius[i] > 0);
    REQUIRE(proj.tile_rect[4 * i + 0] == 0);  // rectangle covers every tile: no culling discontinuity
    REQUIRE(proj.tile_rect[4 * i + 1] == 0);
    REQUIRE(proj.tile_rect[4 * i + 2] == cam.tiles_x());
    REQUIRE(proj.tile_rect[4 * i + 3] == cam.tiles_y());
    for (int ch = 0; ch < 3; ++ch) REQUIRE(proj.clamped[3 * i + static_cast<size_t>(ch)] == 0);
  }
  const auto grads = s4d::ref::render_bwd<kCutoff>(g, cam, kBackground, proj, img, w);
  auto loss = [&] { return weighted_loss(s4d::ref::render_fwd<kCutoff>(g, cam, kBackground).second, w); };

  FdChecker fd;
  fd.check_all(g.means, grads.v_means, loss, "means");
  fd.check_all(g.log_scales, grads.v_log_scales, loss, "log_scales");
  fd.check_all(g.opacity_logits, grads.v_opacity_logits, loss, "opacity_logits");
  if (g.colors.empty())
    fd.check_all(g.sh, grads.v_sh, loss, "sh");
  else
    fd.check_all(g.colors, grads.v_colors, loss, "colors");
  for (size_t i = 0; i < g.size(); ++i) {
    const double* vq = &grads.v_quats[4 * i];
    // The twin normalises, so the loss is flat along q itself: the radial derivative must vanish.
    const double* q = &g.quats[4 * i];
    const double radial = vq[0] * q[0] + vq[1] * q[1] + vq[2] * q[2] + vq[3] * q[3];
    const double vq_norm = std::sqrt(vq[0] * vq[0] + vq[1] * vq[1] + vq[2] * vq[2] + vq[3] * vq[3]);
    CHECK(std::abs(radial) <= 1e-12 * (1 + vq_norm));  // measured 1.1e-16: pure rounding
    for (const auto& t : quat_tangents(q)) {
      std::vector<double> dir(g.quats.size(), 0.0);
      for (size_t k = 0; k < 4; ++k) dir[4 * i + k] = t[k];
      const double analytic = vq[0] * t[0] + vq[1] * t[1] + vq[2] * t[2] + vq[3] * t[3];
      fd.check(g.quats, dir, analytic, loss, "quats tangent of " + std::to_string(i));
    }
  }
  return fd;
}

Gaussians<float> to_float(const Gaussians<double>& g) {
  auto cast = [](const std::vector<double>& v) {
    std::vector<float> out(v.size());
    std::transform(v.begin(), v.end(), out.begin(), [](double x) { return static_cast<float>(x); });
    return out;
  };
  Gaussians<float> f;
  f.means = cast(g.means), f.log_scales = cast(g.log_scales), f.quats = cast(g.quats);
  f.opacity_logits = cast(g.opacity_logits), f.sh = cast(g.sh), f.colors = cast(g.colors);
  f.sh_degree = g.sh_degree;
  return f;
}

Camera<float> to_float(const Camera<double>& c) {
  Camera<float> f;
  for (size_t k = 0; k < 16; ++k) f.world_to_cam[k] = static_cast<float>(c.world_to_cam[k]);
  f.fx = static_cast<float>(c.fx), f.fy = static_cast<float>(c.fy);
  f.cx = static_cast<float>(c.cx), f.cy = static_cast<float>(c.cy);
  f.width = c.width, f.height = c.height;
  return f;
}

// Appends Gaussian i of `src` to `dst` (same SH width and colour mode).
void append_gaussian(Gaussians<double>& dst, const Gaussians<double>& src, size_t i) {
  const size_t K = src.sh_coeffs();
  dst.means.insert(dst.means.end(), src.means.begin() + static_cast<long>(3 * i), src.means.begin() + static_cast<long>(3 * i + 3));
  dst.log_scales.insert(dst.log_scales.end(), src.log_scales.begin() + static_cast<long>(3 * i),
                        src.log_scales.begin() + static_cast<long>(3 * i + 3));
  dst.quats.insert(dst.quats.end(), src.quats.begin() + static_cast<long>(4 * i), src.quats.begin() + static_cast<long>(4 * i + 4));
  dst.opacity_logits.push_back(src.opacity_logits[i]);
  dst.sh.insert(dst.sh.end(), src.sh.begin() + static_cast<long>(3 * K * i), src.sh.begin() + static_cast<long>(3 * K * (i + 1)));
  if (!src.colors.empty())
    dst.colors.insert(dst.colors.end(), src.colors.begin() + static_cast<long>(3 * i), src.colors.begin() + static_cast<long>(3 * i + 3));
}

}  // namespace

TEST_CASE("render backward matches finite differences on the smooth variant with SH degree 3") {
  const FdChecker fd = check_render_gradients(test_scene(3, false));
  MESSAGE("worst |an - num| = " << fd.worst_abs << ", worst error / tolerance = " << fd.worst_ratio);
}

TEST_CASE("render backward matches finite differences on the smooth variant with a colour override") {
  const FdChecker fd = check_render_gradients(test_scene(1, true));
  MESSAGE("worst |an - num| = " << fd.worst_abs << ", worst error / tolerance = " << fd.worst_ratio);
}

TEST_CASE("hard-variant backward is the true gradient where alpha is capped at 0.99 and blending stops early") {
  Gaussians<double> g = test_scene(3, false);
  for (double& logit : g.opacity_logits) logit += 6;  // opacity ~0.997: centres hit the 0.99 cap
  const Camera<double> cam = test_camera();
  const auto [p, img] = s4d::ref::render_fwd(g, cam, kBackground);
  const auto [p_smooth, img_smooth] = s4d::ref::render_fwd<Cutoff::smooth>(g, cam, kBackground);
  const bool stopped_early = std::any_of(img.count.begin(), img.count.end(), [](int c) { return c < 6; });
  CHECK(stopped_early);  // the T < 1e-4 stop is exercised
  int capped = 0;  // (pixel, Gaussian) samples with o*G > 0.99, whether or not blending reached them
  for (size_t i = 0; i < g.size(); ++i)
    for (int y = 0; y < cam.height; ++y)
      for (int x = 0; x < cam.width; ++x) {
        const double dx = p.mean2d[2 * i] - (x + 0.5), dy = p.mean2d[2 * i + 1] - (y + 0.5);
        const double power = -(p.conic[3 * i] * dx * dx + p.conic[3 * i + 2] * dy * dy) / 2 - p.conic[3 * i + 1] * dx * dy;
        capped += p.opacity[i] * std::exp(power) > s4d::ref::kMaxAlpha ? 1 : 0;
      }
  CHECK(capped > 0);
  CHECK_FALSE(s4d::test::allclose_report(img.rgb, img_smooth.rgb, {.atol = 1e-6}, "img.rgb").ok);
  const FdChecker fd = check_render_gradients<Cutoff::hard>(g);
  MESSAGE("worst |an - num| = " << fd.worst_abs << ", worst error / tolerance = " << fd.worst_ratio);
}

TEST_CASE("raster backward gives pixel-unit mean2d and full off-diagonal conic gradients") {
  const Camera<double> cam = test_camera();
  const ImageGrads<double> w = test_weights(cam.width * cam.height);
  Projected<double> proj = s4d::ref::project_fwd(test_scene(2, false), cam);
  const Image<double> img = s4d::ref::raster_fwd<Cutoff::smooth>(proj, cam, kBackground);
  const auto v = s4d::ref::raster_bwd<Cutoff::smooth>(proj, cam, kBackground, img, w);
  auto loss = [&] { return weighted_loss(s4d::ref::raster_fwd<Cutoff::smooth>(proj, cam, kBackground), w); };
  FdChecker fd;
  fd.check_all(proj.mean2d, v.v_mean2d, loss, "mean2d");
  fd.check_all(proj.conic, v.v_conic, loss, "conic");
  fd.check_all(proj.opacity, v.v_opacity, loss, "opacity");
  fd.check_all(proj.rgb, v.v_rgb, loss, "rgb");
  fd.check_all(proj.depth, v.v_depth, loss, "depth");
  MESSAGE("worst |an - num| = " << fd.worst_abs << ", worst error / tolerance = " << fd.worst_ratio);
}

TEST_CASE("float and double forward renders agree") {
  const Camera<double> cam = test_camera();
  const Gaussians<double> g = test_scene(3, false);
  const auto [pd, id] = s4d::ref::render_fwd(g, cam, kBackground);
  const auto [pf, imf] = s4d::ref::render_fwd(to_float(g), to_float(cam), {0.2f, 0.4f, 0.6f});
  CHECK(imf.count == id.count);  // no pixel sits on a cutoff threshold in this scene
  // float rounding through exp and 6-deep compositing, measured with GCC -O3 on x86-64: 1.5e-7 (rgb),
  // 1.7e-7 (alpha), 6.3e-7 (depth, values ~3-5). Bounds are ~5x that to absorb FMA contraction.
  s4d::test::expect_allclose(imf.rgb, id.rgb, {.atol = 1e-6}, "imf.rgb");
  s4d::test::expect_allclose(imf.alpha, id.alpha, {.atol = 1e-6}, "imf.alpha");
  s4d::test::expect_allclose(imf.depth, id.depth, {.atol = 3e-6}, "imf.depth");
}

TEST_CASE("rendering twice is bit-identical") {
  const Camera<double> cam = test_camera();
  const Gaussians<double> g = test_scene(3, false);
  const auto [p1, i1] = s4d::ref::render_fwd(g, cam, kBackground);
  const auto [p2, i2] = s4d::ref::render_fwd(g, cam, kBackground);
  CHECK(i1.rgb == i2.rgb);  // exact on purpose: the twin is deterministic
  CHECK(i1.alpha == i2.alpha);
  CHECK(i1.depth == i2.depth);
  CHECK(i1.last == i2.last);
}

TEST_CASE("culled and transparent Gaussians do not perturb the render") {
  const Camera<double> cam = test_camera();
  const Gaussians<double> g = test_scene(3, false);
  const Image<double> base = s4d::ref::render_fwd(g, cam, kBackground).second;

  Gaussians<double> behind = g;
  append_gaussian(behind, g, 0);
  behind.means[behind.means.size() - 1] = -2.0;  // camera z < 0.2: culled before the tile lists
  append_gaussian(behind, g, 1);
  behind.means[behind.means.size() - 1] = -0.2;  // camera z ~ 0.1: inside the near plane
  const auto [pb, ib] = s4d::ref::render_fwd(behind, cam, kBackground);
  CHECK(pb.radius[6] == 0);
  CHECK(pb.radius[7] == 0);
  s4d::test::expect_allclose(ib.rgb, base.rgb, {}, "ib.rgb");  // culled Gaussians never enter a list: exactly equal
  s4d::test::expect_allclose(ib.depth, base.depth, {}, "ib.depth");

  Gaussians<double> faint = g;
  append_gaussian(faint, g, 2);
  faint.opacity_logits.back() = -30;  // alpha ~ 1e-13 < 1/255: skipped by the hard variant
  const Image<double> fi = s4d::ref::render_fwd(faint, cam, kBackground).second;
  s4d::test::expect_allclose(fi.rgb, base.rgb, {.atol = 1e-12}, "fi.rgb");  // measured 0 (skipped); 1e-12 bounds alpha itself
  CHECK(fi.count == base.count);
}

TEST_CASE("permuting the input order changes the render only by rounding") {
  const Camera<double> cam = test_camera();
  const Gaussians<double> g = test_scene(3, false);
  const ImageGrads<double> w = test_weights(cam.width * cam.height);
  const auto [p, img] = s4d::ref::render_fwd(g, cam, kBackground);
  const auto grads = s4d::ref::render_bwd(g, cam, kBackground, p, img, w);

  const std::vector<size_t> perm = {3, 0, 5, 1, 4, 2};
  Gaussians<double> h;
  h.sh_degree = g.sh_degree;
  for (size_t i : perm) append_gaussian(h, g, i);
  const auto [ph, ih] = s4d::ref::render_fwd(h, cam, kBackground);
  const auto gh = s4d::ref::render_bwd(h, cam, kBackground, ph, ih, w);
  // Distinct depths, so the blend order is the same: measured 0 in double; 1e-12 allows reordering.
  s4d::test::expect_allclose(ih.rgb, img.rgb, {.atol = 1e-12}, "ih.rgb");
  s4d::test::expect_allclose(ih.alpha, img.alpha, {.atol = 1e-12}, "ih.alpha");
  double worst = 0;
  for (size_t j = 0; j < perm.size(); ++j)
    for (size_t k = 0; k < 3; ++k)
      worst = std::max(worst, std::abs(gh.v_means[3 * j + k] - grads.v_means[3 * perm[j] + k]));
  CHECK(worst <= 1e-12);  // measured 0
}

TEST_CASE("hard inputs give finite outputs and gradients") {
  auto run = [](auto scalar) {
    using T = decltype(scalar);
    Camera<double> cd = test_camera(1, 1);
    cd.fx = cd.fy = 2;  // a 1x1 image with a wide field of view
    Gaussians<double> gd = test_scene(3, false);
    gd.quats[0] = gd.quats[1] = gd.quats[2] = gd.quats[3] = 1e-20;  // normalised robustly: same as (1,1,1,1)/2
    for (size_t k = 0; k < 3; ++k) gd.log_scales[3 + k] = std::log(1e-6), gd.log_scales[6 + k] = std::log(1e4);
    gd.opacity_logits[3] = std::log(1e-6 / (1 - 1e-6));   // opacity 1e-6
    gd.opacity_logits[4] = std::log((1 - 1e-6) / 1e-6);   // opacity 1 - 1e-6
    gd.opacity_logits[5] = -30;
    Gaussians<T> g;
    Camera<T> cam;
    if constexpr (std::is_same_v<T, float>)
      g = to_float(gd), cam = to_float(cd);
    else
      g = gd, cam = cd;
    const std::array<T, 3> bg = {T(0.1), T(0.2), T(0.3)};
    ImageGrads<T> w{{T(1), T(-1), T(0.5)}, {T(0.7)}, {T(-0.2)}};
    auto check = [&](auto cutoff) {
      constexpr Cutoff kC = decltype(cutoff)::value;
      const auto [p, img] = s4d::ref::render_fwd<kC>(g, cam, bg);
      const auto gr = s4d::ref::render_bwd<kC>(g, cam, bg, p, img, w);
      CHECK(all_finite(img.rgb));
      CHECK(all_finite(img.alpha));
      CHECK(all_finite(img.depth));
      CHECK(all_finite(gr.v_means));
      CHECK(all_finite(gr.v_log_scales));
      CHECK(all_finite(gr.v_quats));
      CHECK(all_finite(gr.v_opacity_logits));
      CHECK(all_finite(gr.v_sh));
      CHECK(p.radius[0] > 0);
    };
    check(std::integral_constant<Cutoff, Cutoff::hard>{});
    check(std::integral_constant<Cutoff, Cutoff::smooth>{});

    // The tiny quaternion renders like its scaled-up version (the gradient grows as 1/|q| but stays finite).
    Gaussians<T> unit = g;
    for (size_t k = 0; k < 4; ++k) unit.quats[k] = T(0.5);
    const auto a = s4d::ref::render_fwd(g, cam, bg).second, b = s4d::ref::render_fwd(unit, cam, bg).second;
    s4d::test::expect_allclose(a.rgb, b.rgb, {.atol = 1e-6}, "a.rgb");  // measured 0: both normalise to (0.5, 0.5, 0.5, 0.5)
  };
  run(0.0);
  run(0.0f);
}

TEST_CASE("an all-zero quaternion falls back to the identity rotation with zero gradient") {
  const Camera<double> cam = test_camera();
  Gaussians<double> g = test_scene(0, false);
  std::fill(g.quats.begin(), g.quats.begin() + 4, 0.0);
  const auto [p, img] = s4d::ref::render_fwd(g, cam, kBackground);
  const auto gr = s4d::ref::render_bwd(g, cam, kBackground, p, img, test_weights(cam.width * cam.height));
  Gaussians<double> identity = g;
  identity.quats[0] = 1;
  s4d::test::expect_allclose(img.rgb, s4d::ref::render_fwd(identity, cam, kBackground).second.rgb, {}, "img.rgb");  // same code path
  for (size_t k = 0; k < 4; ++k) CHECK(gr.v_quats[k] == 0.0);  // exact: the gradient is not computed
}
