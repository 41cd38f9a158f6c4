// Deterministic random scenes for the rasterizer benchmark, in the CPU twin's layouts so the same
// scene feeds the GPU rasterizer and ref::render_fwd.
#pragma once
#include <cstdint>

#include "s4d/ref/splat_raster_ref.h"
#include "s4d/splat/rasterizer.h"

namespace s4d::bench {

inline constexpr uint32_t kSceneShCoeffs = 16;  // SH coefficients stored per Gaussian and channel (degree 3)

struct SplatScene {
  ref::Gaussians<float> gaussians;  // SH degree 3, kSceneShCoeffs per channel
  ref::Camera<float> camera;        // identity pose, fx = fy = width (a 53 degree horizontal view)
};

// n Gaussians spread over the camera's frustum at depths 2..10. Each one's scale is drawn in pixels
// (sigma log-uniform in 0.7..7 px, anisotropic, so a splat's 3-sigma footprint spans a few to tens
// of pixels at any resolution), then converted to world units at its depth. Rotations, opacities
// (0.12..0.98) and SH coefficients are random. The same (width, height, n, seed) gives the same scene.
SplatScene make_splat_scene(uint32_t width, uint32_t height, uint32_t n, uint32_t seed);

splat::Camera to_gpu_camera(const ref::Camera<float>& cam);

}  // namespace s4d::bench
