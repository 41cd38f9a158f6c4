// Test harness for the GPU rasterizer: uploads twin-layout scenes, runs the GPU forward/backward
// and downloads the results into the twin's own structs so tests compare like with like.
#pragma once
#include <array>
#include <cstdint>
#include <random>
#include <vector>

#include "expect_allclose.h"
#include "s4d/engine/buffer.h"
#include "s4d/engine/context.h"
#include "s4d/ref/splat_raster_ref.h"
#include "s4d/splat/rasterizer.h"

namespace s4d::test {

using Scene = ref::Gaussians<float>;
using Cam = ref::Camera<float>;

// Device copies of a scene's parameters (and gradient buffers of the same shapes).
struct DeviceScene {
  engine::Buffer means, log_scales, quats, opacity_logits, sh, colors;
  engine::Buffer v_means, v_log_scales, v_quats, v_opacity_logits, v_sh, v_colors;
  splat::GaussianParams params;
  splat::GaussianGrads grads;
  DeviceScene(engine::Context& ctx, const Scene& g);
};

splat::Camera gpu_camera(const Cam& cam);

// Each value rounded to the nearest half and back: what a packed half (io::pack_halves) reads as.
std::vector<float> rounded_to_half(const std::vector<float>& values);

// Replaces s's SH buffer with g's SH packed as halves (splat::Storage::f16).
void store_sh_as_halves(engine::Context& ctx, DeviceScene& s, const Scene& g);

struct GpuForward {
  ref::Projected<float> proj;
  ref::Image<float> img;
  uint32_t instances = 0;
  uint32_t longest_tile_list = 0;
};
GpuForward gpu_forward(splat::Rasterizer& r, const DeviceScene& s, const Cam& cam, const std::array<float, 3>& bg);

// Renders `half` (some values stored as halves) and `full` (the same values rounded to halves, stored
// as floats), each with a rasterizer of its own running forward variant `pixels`; checks that the
// projected colours, the image and the alpha are bit for bit equal, and returns half's forward.
GpuForward expect_half_renders_as_float(engine::Context& ctx, const DeviceScene& half, const DeviceScene& full,
                                        const Cam& cam, const std::array<float, 3>& bg, uint32_t pixels);

// Each parameter's gradient in `got` (the GPU's) against `want` (the twin's) within `tol`: means, log
// scales, quaternions, opacity logits, and the colours or the SH, as the scene has.
void expect_param_grads_allclose(const ref::GaussianGrads<float>& got, const ref::GaussianGrads<float>& want, bool colors,
                                 const Tolerance& tol);

struct GpuBackward {
  ref::GaussianGrads<float> grads;    // v_mean2d holds the screen-space mean cotangent from grad2d
  ref::ProjectedGrads<float> grad2d;  // the raster backward's per-Gaussian cotangents
};
GpuBackward gpu_backward(splat::Rasterizer& r, DeviceScene& s, const ref::ImageGrads<float>& v, size_t pixels);

// A camera looking down +z from the origin with a slight rotation, fx ~ width.
Cam random_camera(uint32_t width, uint32_t height, std::mt19937& rng);

// n Gaussians spread over the camera's view at depths 2..8 with random shapes, orientations,
// opacities and SH coefficients of the given degree (K = 16 stored); colours when `colors`.
Scene random_scene(size_t n, int sh_degree, bool colors, std::mt19937& rng);

}  // namespace s4d::test
