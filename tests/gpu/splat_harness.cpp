#include "s4d/engine/buffer_from.h"
#include "expect_equal.h"
#include "s4d/io/half_float.h"
#include "splat_harness.h"

#include <cmath>
#include <string>
#include <vector>

namespace s4d::test {
namespace {

engine::Buffer zeros(engine::Context& ctx, const std::string& name, size_t count) {
  return engine::buffer_from(ctx, name, std::vector<float>(count, 0.0f));
}

}  // namespace

DeviceScene::DeviceScene(engine::Context& ctx, const Scene& g)
    : means(engine::buffer_from(ctx, "means", g.means)),
      log_scales(engine::buffer_from(ctx, "log_scales", g.log_scales)),
      quats(engine::buffer_from(ctx, "quats", g.quats)),
      opacity_logits(engine::buffer_from(ctx, "opacity_logits", g.opacity_logits)),
      sh(engine::buffer_from(ctx, "sh", g.sh)),
      colors(engine::buffer_from(ctx, "colors", g.colors)),
      v_means(zeros(ctx, "v_means", g.means.size())),
      v_log_scales(zeros(ctx, "v_log_scales", g.log_scales.size())),
      v_quats(zeros(ctx, "v_quats", g.quats.size())),
      v_opacity_logits(zeros(ctx, "v_opacity_logits", g.opacity_logits.size())),
      v_sh(zeros(ctx, "v_sh", g.sh.size())),
      v_colors(zeros(ctx, "v_colors", g.colors.size())) {
  const bool use_colors = !g.colors.empty();
  params = {.buffers = {{&means, &log_scales, &quats, &opacity_logits, &sh, use_colors ? &colors : nullptr}},
            .count = static_cast<uint32_t>(g.size()),
            .sh_degree = static_cast<uint32_t>(g.sh_degree),
            .sh_coeffs = static_cast<uint32_t>(std::max<size_t>(1, g.sh_coeffs()))};
  grads = {{&v_means, &v_log_scales, &v_quats, &v_opacity_logits, &v_sh, use_colors ? &v_colors : nullptr}};
}

std::vector<float> rounded_to_half(const std::vector<float>& values) {
  std::vector<float> out(values.size());
  for (size_t k = 0; k < values.size(); ++k) out[k] = io::half_to_float(io::float_to_half(values[k]));
  return out;
}

void store_sh_as_halves(engine::Context& ctx, DeviceScene& s, const Scene& g) {
  s.sh = engine::buffer_from(ctx, "sh halves", io::pack_halves(g.sh));
  s.params.sh_storage = splat::Storage::f16;
}

GpuForward expect_half_renders_as_float(engine::Context& ctx, const DeviceScene& half, const DeviceScene& full,
                                        const Cam& cam, const std::array<float, 3>& bg, uint32_t pixels) {
  splat::Rasterizer r_half(ctx, "half storage", {.forward_pixels = pixels});
  splat::Rasterizer r_full(ctx, "float storage", {.forward_pixels = pixels});
  const GpuForward fh = gpu_forward(r_half, half, cam, bg), ff = gpu_forward(r_full, full, cam, bg);
  expect_equal_arrays(fh.proj.rgb, ff.proj.rgb, "projected colours, half against float storage");
  expect_equal_arrays(fh.img.rgb, ff.img.rgb, "image, half against float storage");
  expect_equal_arrays(fh.img.alpha, ff.img.alpha, "alpha, half against float storage");
  return fh;
}

splat::Camera gpu_camera(const Cam& cam) {
  splat::Camera c;
  for (size_t k = 0; k < 12; ++k) c.world_to_cam[k] = cam.world_to_cam[k];
  c.fx = cam.fx, c.fy = cam.fy, c.cx = cam.cx, c.cy = cam.cy;
  c.width = static_cast<uint32_t>(cam.width), c.height = static_cast<uint32_t>(cam.height);
  return c;
}

GpuForward gpu_forward(splat::Rasterizer& r, const DeviceScene& s, const Cam& cam, const std::array<float, 3>& bg) {
  engine::Context& ctx = r.context();
  const size_t n = s.params.count, npix = static_cast<size_t>(cam.width) * static_cast<size_t>(cam.height);
  GpuForward out;
  const splat::RenderStats stats = r.forward(s.params, gpu_camera(cam), bg);
  out.instances = stats.instances;
  out.longest_tile_list = stats.longest_tile_list;

  const auto xy = ctx.download<float>(r.xy(), 2 * n);
  const auto co = ctx.download<float>(r.conic_opacity(), 4 * n);
  const auto cd = ctx.download<float>(r.color_depth(), 4 * n);
  const auto info = ctx.download<uint32_t>(r.info(), 4 * n);
  auto& p = out.proj;
  p.mean2d = xy;
  p.conic.resize(3 * n), p.opacity.resize(n), p.rgb.resize(3 * n), p.depth.resize(n);
  p.radius.resize(n), p.tile_rect.resize(4 * n), p.clamped.resize(3 * n);
  for (size_t i = 0; i < n; ++i) {
    for (size_t k = 0; k < 3; ++k) {
      p.conic[3 * i + k] = co[4 * i + k];
      p.rgb[3 * i + k] = cd[4 * i + k];
      p.clamped[3 * i + k] = static_cast<uint8_t>((info[4 * i + 3] >> k) & 1u);
    }
    p.opacity[i] = co[4 * i + 3];
    p.depth[i] = cd[4 * i + 3];
    p.radius[i] = static_cast<int>(info[4 * i + 2]);
    p.tile_rect[4 * i + 0] = static_cast<int>(info[4 * i] & 0xFFFFu);
    p.tile_rect[4 * i + 1] = static_cast<int>(info[4 * i] >> 16);
    p.tile_rect[4 * i + 2] = static_cast<int>(info[4 * i + 1] & 0xFFFFu);
    p.tile_rect[4 * i + 3] = static_cast<int>(info[4 * i + 1] >> 16);
  }
  auto& img = out.img;
  img.width = cam.width, img.height = cam.height;
  img.rgb = ctx.download<float>(r.rgb(), 3 * npix);
  img.alpha = ctx.download<float>(r.alpha(), npix);
  img.depth = ctx.download<float>(r.depth(), npix);
  const auto count = ctx.download<uint32_t>(r.contributors(), npix);
  img.count.assign(count.begin(), count.end());
  return out;
}

GpuBackward gpu_backward(splat::Rasterizer& r, DeviceScene& s, const ref::ImageGrads<float>& v, size_t pixels) {
  engine::Context& ctx = r.context();
  const size_t n = s.params.count;
  engine::Buffer v_rgb = engine::buffer_from(ctx, "v_rgb", v.v_rgb);
  engine::Buffer v_alpha = engine::buffer_from(ctx, "v_alpha", v.v_alpha.empty() ? std::vector<float>(pixels, 0.0f) : v.v_alpha);
  engine::Buffer v_depth = engine::buffer_from(ctx, "v_depth", v.v_depth.empty() ? std::vector<float>(pixels, 0.0f) : v.v_depth);
  r.backward(s.params,
             {.v_rgb = &v_rgb, .v_alpha = v.v_alpha.empty() ? nullptr : &v_alpha,
              .v_depth = v.v_depth.empty() ? nullptr : &v_depth},
             s.grads);
  GpuBackward out;
  auto& g = out.grads;
  g.v_means = ctx.download<float>(s.v_means, 3 * n);
  g.v_log_scales = ctx.download<float>(s.v_log_scales, 3 * n);
  g.v_quats = ctx.download<float>(s.v_quats, 4 * n);
  g.v_opacity_logits = ctx.download<float>(s.v_opacity_logits, n);
  if (s.params[splat::Attr::colors]) g.v_colors = ctx.download<float>(s.v_colors, 3 * n);
  else g.v_sh = ctx.download<float>(s.v_sh, 3 * n * s.params.sh_coeffs);
  const auto g2 = ctx.download<float>(r.grad2d(), S4D_G2D_STRIDE * n);
  out.grad2d = ref::ProjectedGrads<float>(n);
  g.v_mean2d.resize(2 * n);
  for (size_t i = 0; i < n; ++i) {
    const float* x = &g2[S4D_G2D_STRIDE * i];
    for (size_t k = 0; k < 2; ++k) out.grad2d.v_mean2d[2 * i + k] = g.v_mean2d[2 * i + k] = x[S4D_G2D_XY + k];
    for (size_t k = 0; k < 3; ++k) {
      out.grad2d.v_conic[3 * i + k] = x[S4D_G2D_CONIC + k];
      out.grad2d.v_rgb[3 * i + k] = x[S4D_G2D_RGB + k];
    }
    out.grad2d.v_opacity[i] = x[S4D_G2D_OPACITY];
    out.grad2d.v_depth[i] = x[S4D_G2D_DEPTH];
  }
  return out;
}

Cam random_camera(uint32_t width, uint32_t height, std::mt19937& rng) {
  std::uniform_real_distribution<float> u(-1, 1);
  const float a = 0.08f * u(rng), c = std::cos(a), s = std::sin(a);
  Cam cam;
  cam.world_to_cam = {c, 0, s, 0.05f * u(rng), 0, 1, 0, 0.05f * u(rng), -s, 0, c, 0.1f * u(rng), 0, 0, 0, 1};
  cam.fx = 0.9f * static_cast<float>(width), cam.fy = 0.95f * static_cast<float>(width);
  cam.cx = 0.5f * static_cast<float>(width) + 1.3f * u(rng), cam.cy = 0.5f * static_cast<float>(height) + 0.7f * u(rng);
  cam.width = static_cast<int>(width), cam.height = static_cast<int>(height);
  return cam;
}

Scene random_scene(size_t n, int sh_degree, bool colors, std::mt19937& rng) {
  std::uniform_real_distribution<float> u(-1, 1), u01(0, 1);
  Scene g;
  g.sh_degree = sh_degree;
  for (size_t i = 0; i < n; ++i) {
    const float z = 2.0f + 6.0f * u01(rng);
    for (float m : {0.7f * z * u(rng), 0.6f * z * u(rng), z}) g.means.push_back(m);
    const float base = std::log(0.01f + 0.08f * u01(rng));
    for (int k = 0; k < 3; ++k) g.log_scales.push_back(base + 0.6f * u(rng));
    for (int k = 0; k < 4; ++k) g.quats.push_back(u(rng));
    g.opacity_logits.push_back(3.0f * u(rng));
    for (int k = 0; k < 16; ++k)
      for (int ch = 0; ch < 3; ++ch) g.sh.push_back(k == 0 ? 1.2f * u(rng) : 0.3f * u(rng));
    if (colors)
      for (int ch = 0; ch < 3; ++ch) g.colors.push_back(u01(rng));
  }
  return g;
}

void expect_param_grads_allclose(const ref::GaussianGrads<float>& got, const ref::GaussianGrads<float>& want, bool colors,
                                 const Tolerance& tol) {
  expect_allclose(got.v_means, want.v_means, tol, "v_means");
  expect_allclose(got.v_log_scales, want.v_log_scales, tol, "v_log_scales");
  expect_allclose(got.v_quats, want.v_quats, tol, "v_quats");
  expect_allclose(got.v_opacity_logits, want.v_opacity_logits, tol, "v_opacity_logits");
  if (colors) expect_allclose(got.v_colors, want.v_colors, tol, "v_colors");
  else expect_allclose(got.v_sh, want.v_sh, tol, "v_sh");
}

}  // namespace s4d::test
