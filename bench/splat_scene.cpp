#include "splat_scene.h"

#include <cmath>
#include <random>
#include <stdexcept>
#include <string>

#include "s4d/engine/buffer_from.h"

namespace s4d::bench {

SplatScene make_splat_scene(uint32_t width, uint32_t height, uint32_t n, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1, 1), u01(0, 1);
  SplatScene s;
  ref::Camera<float>& cam = s.camera;
  cam.world_to_cam = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  cam.fx = cam.fy = static_cast<float>(width);
  cam.cx = 0.5f * static_cast<float>(width), cam.cy = 0.5f * static_cast<float>(height);
  cam.width = static_cast<int>(width), cam.height = static_cast<int>(height);

  ref::Gaussians<float>& g = s.gaussians;
  g.sh_degree = 3;
  for (uint32_t i = 0; i < n; ++i) {
    const float z = 2.0f + 8.0f * u01(rng);
    const float px = static_cast<float>(width) * u01(rng), py = static_cast<float>(height) * u01(rng);
    for (float m : {(px - cam.cx) * z / cam.fx, (py - cam.cy) * z / cam.fy, z}) g.means.push_back(m);
    const float sigma_px = 0.7f * std::pow(10.0f, u01(rng));
    const float base = std::log(sigma_px * z / cam.fx);
    for (int k = 0; k < 3; ++k) g.log_scales.push_back(base + 0.4f * u(rng));
    float q[4], norm2 = 0;
    do {  // a quaternion far from zero, so normalising it in the kernel is well conditioned
      norm2 = 0;
      for (float& c : q) c = u(rng), norm2 += c * c;
    } while (norm2 < 0.01f);
    for (float c : q) g.quats.push_back(c);
    g.opacity_logits.push_back(1.0f + 3.0f * u(rng));
    for (uint32_t k = 0; k < kSceneShCoeffs; ++k)
      for (int ch = 0; ch < 3; ++ch) g.sh.push_back(k == 0 ? 1.2f * u(rng) : 0.3f * u(rng));
  }
  return s;
}

SplatScene to_splat_scene(const io::GaussianCloud& cloud, const io::CameraView& view) {
  SplatScene s;
  s.gaussians = {.means = cloud.means,
                 .log_scales = cloud.log_scales,
                 .quats = cloud.quats,
                 .opacity_logits = cloud.opacity_logits,
                 .sh = cloud.sh,
                 .colors = {},
                 .sh_degree = cloud.sh_degree};
  for (size_t k = 0; k < 16; ++k) s.camera.world_to_cam[k] = static_cast<float>(view.world_to_cam[k]);
  s.camera.fx = static_cast<float>(view.fx), s.camera.fy = static_cast<float>(view.fy);
  s.camera.cx = static_cast<float>(view.cx), s.camera.cy = static_cast<float>(view.cy);
  s.camera.width = view.width, s.camera.height = view.height;
  return s;
}

SplatScene load_splat_scene(const std::filesystem::path& ply, const std::filesystem::path& cameras, size_t camera) {
  const std::vector<io::CameraView> views = io::read_nerf_cameras(cameras);
  if (camera >= views.size())
    throw std::invalid_argument(cameras.string() + ": field 'frames': camera " + std::to_string(camera) +
                                " asked for, the file has " + std::to_string(views.size()));
  return to_splat_scene(io::read_ply_gaussians(ply), views[camera]);
}

splat::Camera to_gpu_camera(const ref::Camera<float>& cam) {
  splat::Camera c;
  for (size_t k = 0; k < 12; ++k) c.world_to_cam[k] = cam.world_to_cam[k];
  c.fx = cam.fx, c.fy = cam.fy, c.cx = cam.cx, c.cy = cam.cy;
  c.width = static_cast<uint32_t>(cam.width), c.height = static_cast<uint32_t>(cam.height);
  return c;
}

DeviceScene::DeviceScene(engine::Context& ctx, const ref::Gaussians<float>& g) {
  const std::vector<float>* host[splat::kCloudAttrCount] = {&g.means, &g.log_scales, &g.quats, &g.opacity_logits,
                                                            &g.sh};
  params = {.count = static_cast<uint32_t>(g.size()),
            .sh_degree = static_cast<uint32_t>(g.sh_degree),
            .sh_coeffs = static_cast<uint32_t>(g.sh_coeffs())};
  for (splat::Attr a : splat::kCloudAttrs) {
    buffers[a] = engine::buffer_from(ctx, std::string("bench ") + splat::attr_name(a), *host[splat::index(a)]);
    params[a] = &buffers[a];
  }
}

size_t DeviceScene::bytes() const {
  size_t total = 0;
  for (const engine::Buffer& b : buffers.items) total += b.size();
  return total;
}

}  // namespace s4d::bench
