// Scenes for the rasterizer benchmarks, in the CPU twin's layouts so the same scene feeds the GPU
// rasterizer and ref::render_fwd: deterministic random ones, and any 3DGS PLY seen by one camera of
// a transforms.json (the peer's scene, peer_scene.h, among them).
#pragma once
#include <cstdint>
#include <filesystem>

#include "s4d/engine/buffer.h"
#include "s4d/engine/context.h"
#include "s4d/io/nerf_cameras.h"
#include "s4d/io/ply_gaussians.h"
#include "s4d/ref/splat_raster_ref.h"
#include "s4d/splat/rasterizer.h"

namespace s4d::bench {

inline constexpr uint32_t kSceneShCoeffs = 16;  // SH coefficients stored per Gaussian and channel (degree 3)

struct SplatScene {
  ref::Gaussians<float> gaussians;
  ref::Camera<float> camera;
};

// n Gaussians spread over the camera's frustum at depths 2..10. Each one's scale is drawn in pixels
// (sigma log-uniform in 0.7..7 px, anisotropic, so a splat's 3-sigma footprint spans a few to tens
// of pixels at any resolution), then converted to world units at its depth. Rotations, opacities
// (0.12..0.98) and SH coefficients are random (SH degree 3, kSceneShCoeffs per channel). The camera
// has the identity pose and fx = fy = width (a 53 degree horizontal view). The same (width, height,
// n, seed) gives the same scene.
SplatScene make_splat_scene(uint32_t width, uint32_t height, uint32_t n, uint32_t seed);

// `cloud` at its full SH degree, seen by `view`.
SplatScene to_splat_scene(const io::GaussianCloud& cloud, const io::CameraView& view);

// A 3DGS PLY seen by camera `camera` (0-based, in file order) of a transforms.json that gives every
// frame's size (w, h). Throws what the readers throw, and std::invalid_argument naming the file
// when there is no such camera.
SplatScene load_splat_scene(const std::filesystem::path& ply, const std::filesystem::path& cameras, size_t camera);

splat::Camera to_gpu_camera(const ref::Camera<float>& cam);

// A scene's parameters on the device, and the rasterizer's view of them (`params` points into this
// object, so it neither copies nor moves).
struct DeviceScene {
  splat::PerAttr<engine::Buffer, splat::kCloudAttrCount> buffers;
  splat::GaussianParams params;

  DeviceScene(engine::Context& ctx, const ref::Gaussians<float>& g);
  DeviceScene(const DeviceScene&) = delete;
  DeviceScene& operator=(const DeviceScene&) = delete;
  size_t bytes() const;
};

}  // namespace s4d::bench
