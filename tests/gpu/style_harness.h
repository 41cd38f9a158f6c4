// Test harness for the style rasterizer: device copies of a twin StyleMlp, attached to a
// test::DeviceScene, and random MLP weights.
#pragma once
#include <random>
#include <vector>

#include "s4d/ref/style_raster_ref.h"
#include "splat_harness.h"

namespace s4d::test {

// The weights and their gradient buffer on the device, and the rasterizer's description of them.
// Not movable: DeviceScene::params points at `desc`.
struct DeviceStyle {
  engine::Buffer weights, v_mlp;
  splat::StyleMlp desc;
  DeviceStyle(engine::Context& ctx, const ref::StyleMlp<float>& mlp);
  DeviceStyle(const DeviceStyle&) = delete;
  DeviceStyle& operator=(const DeviceStyle&) = delete;
  void attach(DeviceScene& scene) {
    scene.params.style = &desc;
    scene.params[splat::Attr::style_mlp] = &weights;
    scene.grads[splat::Attr::style_mlp] = &v_mlp;
  }
  std::vector<float> download_v_mlp(engine::Context& ctx) const;
  // Replaces the weights with `mlp`'s packed as halves (splat::Storage::f16) in `scene`, attached.
  void store_as_halves(engine::Context& ctx, const ref::StyleMlp<float>& mlp, DeviceScene& scene);
};

// Random cotangents on rgb, and on alpha and depth when `alpha_depth`.
ref::ImageGrads<float> random_cotangents(const Cam& cam, std::mt19937& rng, bool alpha_depth);

// One 16x16 tile looking down +z, fx = fy = 16.
Cam tile_camera();

// Appends an isotropic Gaussian at pixel (u, v) and depth z with a pixel-space sigma, an opacity and
// a random degree-0 colour.
void add_gaussian(Scene& g, const Cam& cam, float u, float v, float z, float sigma_px, float opacity,
                  std::mt19937& rng);

// n MLPs with weights and biases uniform in (-1, 1) (every gradient is exercised), time 0.37.
ref::StyleMlp<float> random_mlp(size_t n, ref::StyleDepth depth, bool input_sigmoid, std::mt19937& rng);

}  // namespace s4d::test
