// The renderer's exact optical flow (training/kernels/splat/include/s4d/splat/exact_flow.h): its kernels
// against their CPU twins, the analytic flow of a fronto-parallel plane under a camera translation,
// the warp loss of two renders under that flow, and zero-area Gaussians (docs/kernel-extremes.md).
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <vector>

#include "expect_allclose.h"
#include "s4d/engine/buffer_from.h"
#include "s4d/metrics/warp_loss.h"
#include "s4d/ref/flow_ref.h"
#include "s4d/splat/exact_flow.h"
#include "splat_harness.h"
#include "test_context.h"

namespace {

using s4d::test::Cam;
using s4d::test::Scene;

// A camera at `position` looking down +z (identity rotation), 64x48, f = 60.
Cam camera_at(float x, float y, float z) {
  Cam c;
  c.world_to_cam = {1, 0, 0, -x, 0, 1, 0, -y, 0, 0, 1, -z, 0, 0, 0, 1};
  c.fx = c.fy = 60, c.cx = 32, c.cy = 24;
  c.width = 64, c.height = 48;
  return c;
}

// A plane z = depth of overlapping round Gaussians on a 0.1 grid over [-4, 4] x [-3, 3] (wider than
// both views), opaque, coloured by smooth waves of 1.4-2 world units (17-24 px at depth 5) with
// random phases: a wall filling the image whose texture bilinear resampling reproduces closely.
Scene textured_plane(float depth, std::mt19937& rng) {
  std::uniform_real_distribution<float> phase(0.0f, 6.2831853f);
  const float px[3] = {phase(rng), phase(rng), phase(rng)}, py[3] = {phase(rng), phase(rng), phase(rng)};
  const float kx[3] = {4.2f, 3.5f, 3.1f}, ky[3] = {3.3f, 3.9f, 4.5f};  // 2 pi / wavelength
  Scene s;
  for (int j = -30; j <= 30; ++j)
    for (int i = -40; i <= 40; ++i) {
      s.means.insert(s.means.end(), {0.1f * float(i), 0.1f * float(j), depth});
      s.log_scales.insert(s.log_scales.end(), {std::log(0.1f), std::log(0.1f), std::log(0.01f)});
      s.quats.insert(s.quats.end(), {1, 0, 0, 0});
      s.opacity_logits.push_back(4.0f);
      for (int c = 0; c < 3; ++c)
        s.colors.push_back(0.5f + 0.2f * std::sin(kx[c] * 0.1f * float(i) + px[c]) + 0.2f * std::cos(ky[c] * 0.1f * float(j) + py[c]));
    }
  s.sh.assign(s.size() * 3, 0.0f);
  return s;
}

s4d::metrics::Flow as_flow(const s4d::splat::FlowImage& f) {
  s4d::metrics::Flow out{int(f.width), int(f.height), std::vector<float>(f.u.size() * 2)};
  for (size_t k = 0; k < f.u.size(); ++k) out.uv[2 * k] = f.u[k], out.uv[2 * k + 1] = f.v[k];
  return out;
}

// Flow rendered at frame `at` (scene s seen from `cam_at`) towards the frame seen from `cam_to`.
s4d::splat::FlowImage exact_flow(s4d::splat::Rasterizer& r, const s4d::test::DeviceScene& s, const Cam& cam_at,
                                 const Cam& cam_to) {
  s4d::engine::Context& ctx = s4d::test::context();
  const size_t bytes = size_t{s.params.count} * 12;
  s4d::engine::Buffer from(ctx, "screen at", bytes), to(ctx, "screen to", bytes), disp(ctx, "displacement", bytes);
  s4d::splat::project_means(ctx, s.params, s4d::test::gpu_camera(cam_at), from);
  s4d::splat::project_means(ctx, s.params, s4d::test::gpu_camera(cam_to), to);
  s4d::splat::screen_displacement(ctx, from, to, s.params.count, disp);
  return s4d::splat::render_flow(r, s.params, disp, s4d::test::gpu_camera(cam_at));
}

}  // namespace

TEST_CASE("flow_project and flow_displace match their CPU twins, including means behind the near plane") {
  s4d::engine::Context& ctx = s4d::test::context();
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> xy(-3, 3), z(-1, 8);
  const size_t n = 1000;
  std::vector<float> means(3 * n);
  for (size_t i = 0; i < n; ++i) means[3 * i] = xy(rng), means[3 * i + 1] = xy(rng), means[3 * i + 2] = z(rng);
  const Cam a = s4d::test::random_camera(64, 48, rng), b = s4d::test::random_camera(64, 48, rng);
  s4d::engine::Buffer dev_means = s4d::engine::buffer_from(ctx, "means", means);
  s4d::engine::Buffer sa(ctx, "screen a", n * 12), sb(ctx, "screen b", n * 12), colors(ctx, "colors", n * 12);
  s4d::splat::GaussianParams g;
  g[s4d::splat::Attr::means] = &dev_means;
  g.count = static_cast<uint32_t>(n);
  s4d::splat::project_means(ctx, g, s4d::test::gpu_camera(a), sa);
  s4d::splat::project_means(ctx, g, s4d::test::gpu_camera(b), sb);
  s4d::splat::screen_displacement(ctx, sa, sb, g.count, colors);

  const std::vector<float> gpu_a = ctx.download<float>(sa, 3 * n), gpu_b = ctx.download<float>(sb, 3 * n);
  const std::vector<float> twin_a = s4d::ref::flow_project(means, a), twin_b = s4d::ref::flow_project(means, b);
  size_t invalid = 0;
  for (size_t i = 0; i < n; ++i) {
    REQUIRE_MESSAGE(gpu_a[3 * i + 2] == twin_a[3 * i + 2], "validity of Gaussian " << i);  // 0 or 1 exactly
    invalid += twin_a[3 * i + 2] == 0.0f;
  }
  CHECK(invalid > 50);  // z in [-1, 8]: about 13 % lie behind the near plane
  // Measured worst case on lavapipe (Mesa 22.3.6): 0, identical. Other devices may fuse multiply-adds;
  // with means near the plane projecting to ~1e4 px, that moves u by up to ~1e-3 (one float ulp).
  s4d::test::expect_allclose(gpu_a, twin_a, {.atol = 1e-3}, "gpu_a");
  s4d::test::expect_allclose(gpu_b, twin_b, {.atol = 1e-3}, "gpu_b");
  // flow_displace from the GPU lanes: one subtraction, bit-identical on every device.
  s4d::test::expect_allclose(ctx.download<float>(colors, 3 * n), s4d::ref::flow_displace(gpu_a, gpu_b), {}, "colors");
}

TEST_CASE("exact flow of a camera translation over a fronto-parallel plane is the analytic flow") {
  std::mt19937 rng(3);
  const float depth = 5.0f, tx = 0.13f, ty = -0.07f;
  const s4d::test::DeviceScene s(s4d::test::context(), textured_plane(depth, rng));
  s4d::splat::Rasterizer r(s4d::test::context());
  const Cam c0 = camera_at(0, 0, 0), c1 = camera_at(tx, ty, 0);
  // A point X projects to u = f (X - tx) / depth + cx: every pixel moves by -f t / depth.
  const double du = -60.0 * tx / depth, dv = -60.0 * ty / depth;
  const s4d::splat::FlowImage fw = exact_flow(r, s, c0, c1), bw = exact_flow(r, s, c1, c0);
  double worst = 0;
  for (size_t k = 0; k < fw.u.size(); ++k) {
    worst = std::max({worst, std::abs(fw.u[k] - du), std::abs(fw.v[k] - dv)});
    worst = std::max({worst, std::abs(bw.u[k] + du), std::abs(bw.v[k] + dv)});
  }
  // Every contributing Gaussian moves by the same amount, so only the blend's float sums separate
  // sum(w d) / (1 - T) from d. Measured worst case on lavapipe (Mesa 22.3.6): 2.3e-6 px for a
  // 1.56 px flow; the bound allows 4x for other devices' summation rounding.
  CHECK(worst <= 1e-5);
}

TEST_CASE("warping the next frame by the exact flow reproduces the frame") {
  std::mt19937 rng(5);
  const s4d::test::DeviceScene s(s4d::test::context(), textured_plane(5.0f, rng));
  s4d::splat::Rasterizer r(s4d::test::context());
  const Cam c0 = camera_at(0, 0, 0), c1 = camera_at(0.21f, 0.12f, 0.3f);  // moves sideways and towards the plane
  auto render = [&](const Cam& c) {
    const s4d::test::GpuForward f = s4d::test::gpu_forward(r, s, c, {0, 0, 0});
    return s4d::io::ImageF{c.width, c.height, 3, f.img.rgb};
  };
  const s4d::io::ImageF f0 = render(c0), f1 = render(c1);
  const s4d::metrics::Flow fw = as_flow(exact_flow(r, s, c0, c1)), bw = as_flow(exact_flow(r, s, c1, c0));
  const s4d::metrics::Flow zero{fw.width, fw.height, std::vector<float>(fw.uv.size(), 0.0f)};
  // Away from the border, where frame 0 sees what frame 1 does not (the camera moves 2.5 px sideways
  // and 6 % closer, so up to ~5 px leave the view), frame 1 warped back matches frame 0.
  auto interior_error = [&](const s4d::metrics::Flow& flow) {
    const s4d::io::ImageF warped = s4d::metrics::warp_back(f1, flow);
    double sum = 0;
    int count = 0;
    for (int y = 6; y < f0.height - 6; ++y)
      for (int x = 6; x < f0.width - 6; ++x)
        for (int c = 0; c < 3; ++c, ++count) {
          const size_t k = size_t(3 * (y * f0.width + x) + c);
          sum += std::abs(warped.data[k] - f0.data[k]);
        }
    return sum / count;
  };
  s4d::metrics::Flow off = fw;  // the exact flow half a pixel off
  for (size_t k = 0; k < off.uv.size(); k += 2) off.uv[k] += 0.5f;
  const double interior = interior_error(fw), interior_off = interior_error(off);
  const s4d::metrics::PairWarpError exact = s4d::metrics::warp_error(f0, f1, fw, bw);
  const s4d::metrics::PairWarpError none = s4d::metrics::warp_error(f0, f1, zero, zero);
  // Colours span [0.1, 0.9]. Measured on lavapipe (Mesa 22.3.6): interior 0.00328 (bilinear
  // resampling of the waves and the splats' own ripple), 0.0162 with the flow half a pixel off;
  // whole-image warp loss 0.0108 (the border band) against 0.101 without flow.
  CHECK(interior <= 0.0035);
  CHECK(interior * 4 < interior_off);
  CHECK(exact.error * 5 < none.error);
  CHECK(exact.valid_fraction > 0.9);  // measured 1.0: the occlusion check flags nothing on a plane
}

TEST_CASE("exact flow over zero-area Gaussians (zero scales, discs seen edge-on) is finite and equals the twin") {
  std::mt19937 rng(11);
  const Cam a = s4d::test::random_camera(48, 32, rng), b = s4d::test::random_camera(48, 32, rng);
  Scene g = s4d::test::random_scene(40, 0, true, rng);
  for (size_t i = 0; i < g.size(); ++i) {
    float* ls = &g.log_scales[3 * i];
    if (i % 2 == 0) ls[0] = ls[1] = ls[2] = -100.0f;  // exp(-100) is 0 in float: only the 0.3 px dilation is left
    if (i % 4 == 1) {  // a disc in the y-z plane, seen edge-on by a camera looking down +z
      ls[0] = -100.0f;
      std::copy_n(std::array<float, 4>{1, 0, 0, 0}.begin(), 4, &g.quats[4 * i]);
    }
  }
  const s4d::test::DeviceScene s(s4d::test::context(), g);
  s4d::splat::Rasterizer r(s4d::test::context());
  const s4d::splat::FlowImage flow = exact_flow(r, s, a, b);
  // The twin: the same blend of the twins' displacements, divided by alpha as render_flow does.
  Scene coloured = g;
  coloured.colors = s4d::ref::flow_displace(s4d::ref::flow_project(g.means, a), s4d::ref::flow_project(g.means, b));
  const auto [proj, img] = s4d::ref::render_fwd(coloured, a, {0.0f, 0.0f, 0.0f});
  std::vector<float> u(flow.u.size(), 0.0f), v(flow.v.size(), 0.0f);
  size_t covered = 0;
  for (size_t k = 0; k < u.size(); ++k) {
    if (!(img.alpha[k] > 1e-6f)) continue;
    u[k] = img.rgb[3 * k] / img.alpha[k], v[k] = img.rgb[3 * k + 1] / img.alpha[k];
    ++covered;
  }
  CHECK(covered > 100);
  // The GPU's and the float twin's blends differ by rounding, which dividing by an alpha as small as
  // 1/255 magnifies: measured worst 5.8e-5 px (u, of a 5 px flow) on lavapipe (Mesa 22.3.6).
  s4d::test::expect_allclose(flow.u, u, {.atol = 1e-4, .rtol = 1e-5}, "flow u");
  s4d::test::expect_allclose(flow.v, v, {.atol = 1e-4, .rtol = 1e-5}, "flow v");
}
