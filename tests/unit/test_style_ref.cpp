// The style rasterizer's CPU twin (training/ref/include/s4d/ref/style_{mlp,raster}_ref.h): backward
// against central finite differences in double on the smooth-cutoff variant for the MLP weights,
// SH / colours and opacities in both depth modes with and without the input sigmoid; geometry
// gradients where the depth feature has no effect; the hard variant around the 0.99 cap; and the
// zeroed last layer reproducing the plain twin bit for bit.
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <random>
#include <string>
#include <vector>

#include "expect_allclose.h"
#include "fd_check.h"
#include "s4d/ref/style_raster_ref.h"

namespace {

using s4d::ref::Camera;
using s4d::ref::Cutoff;
using s4d::ref::Gaussians;
using s4d::ref::Image;
using s4d::ref::ImageGrads;
using s4d::ref::StyleDepth;
using s4d::ref::StyleMlp;
using s4d::test::FdChecker;

constexpr std::array<double, 3> kBackground = {0.2, 0.4, 0.6};

// 24x20 (2x2 tiles, partial ones), slightly rotated and off-centre.
Camera<double> test_camera() {
  Camera<double> cam;
  const double ang = 0.1, c = std::cos(ang), s = std::sin(ang);
  cam.world_to_cam = {c, 0, s, 0.1, 0, 1, 0, -0.05, -s, 0, c, 0.3, 0, 0, 0, 1};
  cam.fx = 22, cam.fy = 21, cam.cx = 12.3, cam.cy = 9.8;
  cam.width = 24, cam.height = 20;
  return cam;
}

// Six Gaussians with distinct depths whose tile rectangles cover the whole image, colours above
// the SH clamp (as test_splat_ref.cpp's scene).
Gaussians<double> test_scene(bool color_override) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  Gaussians<double> g;
  g.sh_degree = 2;
  for (int i = 0; i < 6; ++i) {
    const double z = 3.0 + 0.37 * i;
    for (double m : {0.25 * u(rng) * z / 3, 0.25 * u(rng) * z / 3, z}) g.means.push_back(m);
    for (int k = 0; k < 3; ++k) g.log_scales.push_back(std::log(0.9 + 0.2 * u(rng)));
    for (int k = 0; k < 4; ++k) g.quats.push_back((k == 0 ? 1.2 : 0.0) + 0.5 * u(rng));
    g.opacity_logits.push_back(0.3 * u(rng));
    for (int k = 0; k < 16; ++k)
      for (int ch = 0; ch < 3; ++ch) g.sh.push_back(k == 0 ? 0.4 + 0.2 * u(rng) : 0.05 * u(rng));
    if (color_override)
      for (int ch = 0; ch < 3; ++ch) g.colors.push_back(0.5 + 0.4 * u(rng));
  }
  return g;
}

// Random weights and biases in (-1, 1): every weight's gradient is exercised, and the outputs move
// the colour and the opacity by O(0.1-0.5).
StyleMlp<double> test_mlp(size_t n, StyleDepth depth, bool input_sigmoid) {
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> u(-1, 1);
  StyleMlp<double> mlp;
  for (size_t k = 0; k < n * s4d::ref::kStyleMlpStride; ++k) mlp.weights.push_back(u(rng));
  mlp.time = 0.37, mlp.depth = depth, mlp.depth_scale = 0.8, mlp.input_sigmoid = input_sigmoid;
  return mlp;
}

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

// FD of the full style render for the MLP weights and opacities, the SH or colours when `colours`,
// and the geometry when `geometry` (only valid where the MLP ignores the depth feature, since t* is
// detached).
template <Cutoff kCutoff = Cutoff::smooth>
FdChecker check_style_gradients(Gaussians<double> g, StyleMlp<double> mlp, bool colours = true,
                                bool geometry = false) {
  const Camera<double> cam = test_camera();
  const ImageGrads<double> w = test_weights(cam.width * cam.height);
  const auto fwd = s4d::ref::render_style_fwd<kCutoff>(g, mlp, cam, kBackground);
  for (size_t i = 0; i < g.size(); ++i) {
    REQUIRE(fwd.proj.tile_rect[4 * i + 2] - fwd.proj.tile_rect[4 * i] == cam.tiles_x());  // no tile culling
    REQUIRE(fwd.proj.tile_rect[4 * i + 3] - fwd.proj.tile_rect[4 * i + 1] == cam.tiles_y());
    for (size_t ch = 0; ch < 3; ++ch) REQUIRE(fwd.proj.clamped[3 * i + ch] == 0);
  }
  const auto grads = s4d::ref::render_style_bwd<kCutoff>(g, mlp, cam, kBackground, fwd, w);
  auto loss = [&] { return weighted_loss(s4d::ref::render_style_fwd<kCutoff>(g, mlp, cam, kBackground).img, w); };
  FdChecker fd;
  fd.check_all(mlp.weights, grads.v_mlp, loss, "mlp");
  fd.check_all(g.opacity_logits, grads.g.v_opacity_logits, loss, "opacity_logits");
  if (colours && g.colors.empty()) fd.check_all(g.sh, grads.g.v_sh, loss, "sh");
  if (colours && !g.colors.empty()) fd.check_all(g.colors, grads.g.v_colors, loss, "colors");
  if (geometry) {
    fd.check_all(g.means, grads.g.v_means, loss, "means");
    fd.check_all(g.log_scales, grads.g.v_log_scales, loss, "log_scales");
    for (size_t i = 0; i < g.size(); ++i)
      for (const auto& t : s4d::test::quat_tangents(&g.quats[4 * i])) {
        std::vector<double> dir(g.quats.size(), 0.0);
        double analytic = 0;
        for (size_t k = 0; k < 4; ++k) dir[4 * i + k] = t[k], analytic += grads.g.v_quats[4 * i + k] * t[k];
        fd.check(g.quats, dir, analytic, loss, "quats tangent of " + std::to_string(i));
      }
  }
  return fd;
}

}  // namespace

// The FD rule is FdChecker's (fd_check.h): |an - num| <= 1e-6 + 1e-5 max(|an|, |num|), central
// differences in double with step 1e-6 max(1, |x|). Measured worst over the cases below (GCC -O3,
// x86-64): |an - num| = 3.9e-8, 0.035 of the allowance; a wrong term gives O(1) errors.
TEST_CASE("style backward matches finite differences for MLP weights, SH and opacity") {
  for (const StyleDepth depth : {StyleDepth::ndc, StyleDepth::relative})
    for (const bool sigmoid : {false, true}) {
      CAPTURE(static_cast<int>(depth));
      CAPTURE(sigmoid);
      // The SH path does not depend on the depth mode or the sigmoid: checked once.
      const bool sh = depth == StyleDepth::ndc && !sigmoid;
      const FdChecker fd = check_style_gradients(test_scene(false), test_mlp(6, depth, sigmoid), sh);
      MESSAGE("worst |an - num| = " << fd.worst_abs << ", worst error / tolerance = " << fd.worst_ratio);
    }
}

TEST_CASE("style backward matches finite differences with a colour override") {
  const FdChecker fd = check_style_gradients(test_scene(true), test_mlp(6, StyleDepth::relative, true));
  MESSAGE("worst |an - num| = " << fd.worst_abs << ", worst error / tolerance = " << fd.worst_ratio);
}

TEST_CASE("style geometry gradients match finite differences where the depth feature has no effect") {
  StyleMlp<double> mlp = test_mlp(6, StyleDepth::ndc, false);
  for (size_t i = 0; i < 6; ++i)  // W1's second column: the depth feature's weights
    for (size_t r = 0; r < 4; ++r) mlp.weights[s4d::ref::kStyleMlpStride * i + S4D_STYLE_MLP_W1 + 4 + r] = 0;
  const FdChecker fd = check_style_gradients(test_scene(false), mlp, false, true);
  MESSAGE("worst |an - num| = " << fd.worst_abs << ", worst error / tolerance = " << fd.worst_ratio);
}

TEST_CASE("hard-variant style backward is the true gradient where alpha is capped at 0.99") {
  Gaussians<double> g = test_scene(false);
  for (double& logit : g.opacity_logits) logit += 6;  // o' ~ 1 +- 0.5: centres hit the 0.99 cap
  const StyleMlp<double> mlp = test_mlp(6, StyleDepth::ndc, true);
  const Camera<double> cam = test_camera();
  const auto fwd = s4d::ref::render_style_fwd(g, mlp, cam, kBackground);
  CHECK(std::any_of(fwd.img.count.begin(), fwd.img.count.end(), [](int c) { return c < 6; }));  // stops early
  int capped = 0;  // (pixel, Gaussian) samples with o' G > 0.99
  const s4d::ref::StylePairs<double> pairs{fwd.proj, fwd.quadric, mlp};
  for (size_t i = 0; i < g.size(); ++i)
    for (int y = 0; y < cam.height; ++y)
      for (int x = 0; x < cam.width; ++x)
        capped += pairs.sample<Cutoff::hard>(i, s4d::ref::detail::pixel_ray(cam, x, y)).s.clamped;
  CHECK(capped > 0);
  const auto smooth = s4d::ref::render_style_fwd<Cutoff::smooth>(g, mlp, cam, kBackground);
  CHECK_FALSE(s4d::test::allclose_report(fwd.img.rgb, smooth.img.rgb, {.atol = 1e-3}, "fwd.img.rgb").ok);  // the cap and the stop changed the image
  const FdChecker fd = check_style_gradients<Cutoff::hard>(g, mlp, false);
  MESSAGE("worst |an - num| = " << fd.worst_abs << ", worst error / tolerance = " << fd.worst_ratio);
}

TEST_CASE("a zeroed last layer renders and differentiates exactly like the plain twin") {
  const Camera<double> cam = test_camera();
  const Gaussians<double> g = test_scene(false);
  StyleMlp<double> mlp = test_mlp(6, StyleDepth::relative, true);
  for (size_t i = 0; i < 6; ++i)
    std::fill_n(mlp.weights.begin() + static_cast<long>(s4d::ref::kStyleMlpStride * i + S4D_STYLE_MLP_W3), 20, 0.0);
  const ImageGrads<double> w = test_weights(cam.width * cam.height);
  const auto style = s4d::ref::render_style_fwd(g, mlp, cam, kBackground);
  const auto [proj, plain] = s4d::ref::render_fwd(g, cam, kBackground);
  // Bit-exact: sigmoid(0) = 0.5 exactly, so dRGB and dO are exactly 0 and every sum runs in the
  // plain twin's order.
  CHECK(style.img.rgb == plain.rgb);
  CHECK(style.img.alpha == plain.alpha);
  CHECK(style.img.depth == plain.depth);
  CHECK(style.img.last == plain.last);
  const auto sg = s4d::ref::style_raster_bwd(style.proj, style.quadric, mlp, cam, kBackground, style.img, w);
  const auto pg = s4d::ref::raster_bwd(proj, cam, kBackground, plain, w);
  CHECK(sg.g2d.v_mean2d == pg.v_mean2d);
  CHECK(sg.g2d.v_conic == pg.v_conic);
  CHECK(sg.g2d.v_opacity == pg.v_opacity);
  CHECK(sg.g2d.v_rgb == pg.v_rgb);
  CHECK(sg.g2d.v_depth == pg.v_depth);
  CHECK_FALSE(s4d::test::allclose_report(sg.v_mlp, std::vector<double>(sg.v_mlp.size(), 0.0), {.atol = 1e-3}, "sg.v_mlp").ok);  // W3 and b3 still learn
}

TEST_CASE("t* maximises the Gaussian's density along the pixel ray") {
  const Camera<double> cam = test_camera();
  const Gaussians<double> g = test_scene(false);
  const auto quadric = s4d::ref::style_quadric(g, cam);
  const StyleMlp<double> rel = {{}, 0, StyleDepth::relative, 1, false};
  for (size_t i = 0; i < g.size(); ++i) {
    // Independent of the quadric: the camera-space covariance W Sigma W^T inverted by cofactors.
    const auto p = s4d::ref::detail::project_one(g, i, cam);
    std::array<double, 9> S{};
    for (size_t r = 0; r < 3; ++r)
      for (size_t c = 0; c < 3; ++c)
        for (size_t k = 0; k < 3; ++k)
          for (size_t l = 0; l < 3; ++l) S[3 * r + c] += p.W[3 * r + k] * p.sigma[3 * k + l] * p.W[3 * c + l];
    const std::array<double, 9> cof = {S[4] * S[8] - S[5] * S[7], S[2] * S[7] - S[1] * S[8], S[1] * S[5] - S[2] * S[4],
                                       S[5] * S[6] - S[3] * S[8], S[0] * S[8] - S[2] * S[6], S[2] * S[3] - S[0] * S[5],
                                       S[3] * S[7] - S[4] * S[6], S[1] * S[6] - S[0] * S[7], S[0] * S[4] - S[1] * S[3]};
    const double det = S[0] * cof[0] + S[1] * cof[3] + S[2] * cof[6];
    for (const std::array<double, 2>& ray : {std::array<double, 2>{0.1, -0.2}, std::array<double, 2>{-0.3, 0.05}}) {
      const double rx = ray[0], ry = ray[1];  // the lambda below captures these
      auto mahalanobis = [&](double t) {
        const std::array<double, 3> d = {t * rx - p.t[0], t * ry - p.t[1], t - p.t[2]};
        double m = 0;
        for (size_t r = 0; r < 3; ++r)
          for (size_t c = 0; c < 3; ++c) m += d[r] * cof[3 * r + c] / det * d[c];
        return m;
      };
      const double* qi = &quadric[s4d::ref::kStyleQuadricStride * i];
      const double t_star = p.t[2] + s4d::ref::detail::style_depth_feature(qi, p.t[2], rx, ry, rel);
      // The minimum of a quadratic with curvature ~1/s^2 ~ 1: a 1e-3 step raises it by ~1e-6.
      CHECK(mahalanobis(t_star) < mahalanobis(t_star + 1e-3));
      CHECK(mahalanobis(t_star) < mahalanobis(t_star - 1e-3));
    }
  }
}
