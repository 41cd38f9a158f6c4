#include "style_harness.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "s4d/engine/buffer_from.h"
#include "s4d/io/half_float.h"

namespace s4d::test {

DeviceStyle::DeviceStyle(engine::Context& ctx, const ref::StyleMlp<float>& mlp)
    : weights(engine::buffer_from(ctx, "style weights", mlp.weights)),
      v_mlp(engine::buffer_from(ctx, "v_style_mlp", std::vector<float>(mlp.weights.size(), 0.0f))) {
  desc = {.time = mlp.time,
          .depth = static_cast<splat::StyleDepth>(mlp.depth),
          .depth_scale = mlp.depth_scale,
          .input_sigmoid = mlp.input_sigmoid};
}

std::vector<float> DeviceStyle::download_v_mlp(engine::Context& ctx) const {
  return ctx.download<float>(v_mlp, v_mlp.size() / 4);
}

void DeviceStyle::store_as_halves(engine::Context& ctx, const ref::StyleMlp<float>& mlp, DeviceScene& scene) {
  weights = engine::buffer_from(ctx, "style weights halves", io::pack_halves(mlp.weights));
  attach(scene);
  scene.params.style_mlp_storage = splat::Storage::f16;
}

ref::ImageGrads<float> random_cotangents(const Cam& cam, std::mt19937& rng, bool alpha_depth) {
  std::uniform_real_distribution<float> u(-1, 1);
  ref::ImageGrads<float> v;
  const size_t npix = static_cast<size_t>(cam.width * cam.height);
  for (size_t k = 0; k < 3 * npix; ++k) v.v_rgb.push_back(u(rng));
  if (alpha_depth)
    for (size_t k = 0; k < npix; ++k) v.v_alpha.push_back(u(rng)), v.v_depth.push_back(0.1f * u(rng));
  return v;
}

Cam tile_camera() {
  Cam cam;
  cam.world_to_cam = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  cam.fx = cam.fy = 16, cam.cx = cam.cy = 8, cam.width = cam.height = 16;
  return cam;
}

void add_gaussian(Scene& g, const Cam& cam, float u, float v, float z, float sigma_px, float opacity,
                  std::mt19937& rng) {
  std::uniform_real_distribution<float> u01(0, 1);
  for (float m : {(u - cam.cx) * z / cam.fx, (v - cam.cy) * z / cam.fy, z}) g.means.push_back(m);
  for (int k = 0; k < 3; ++k) g.log_scales.push_back(std::log(sigma_px * z / cam.fx));
  for (float q : {1.0f, 0.0f, 0.0f, 0.0f}) g.quats.push_back(q);
  g.opacity_logits.push_back(std::log(opacity / (1 - opacity)));
  for (int ch = 0; ch < 3; ++ch) g.sh.push_back(u01(rng));
}

ref::StyleMlp<float> random_mlp(size_t n, ref::StyleDepth depth, bool input_sigmoid, std::mt19937& rng) {
  std::uniform_real_distribution<float> u(-1, 1);
  ref::StyleMlp<float> mlp;
  for (size_t k = 0; k < n * ref::kStyleMlpStride; ++k) mlp.weights.push_back(u(rng));
  mlp.time = 0.37f, mlp.depth = depth, mlp.input_sigmoid = input_sigmoid;
  return mlp;
}

}  // namespace s4d::test
