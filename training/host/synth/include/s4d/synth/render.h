// Renders one view of the synthetic scene on the CPU: analytic ray casting (never the project's
// splatting code, so the dataset is an independent ground truth), antialiased with stratified
// jittered samples, rows shared among std::threads.
#pragma once
#include <cstdint>
#include <vector>

#include "s4d/synth/camera_rig.h"
#include "s4d/synth/scene.h"

namespace s4d::synth {

struct RenderSettings {
  int samples_per_axis = 2;  // samples_per_axis^2 jittered samples per pixel
  uint64_t seed = 0;
  int threads = 0;  // 0: std::thread::hardware_concurrency()
};

struct RenderedView {
  int width = 0, height = 0;
  std::vector<float> rgb;  // [H, W, 3] in [0, 1]
  std::vector<float> alpha;  // [H, W]: the share of the pixel's samples that hit a surface
  // Range of view depth over every sample that hit a surface; min > max when none did.
  double min_depth = 0, max_depth = 0;
};

// The jitter depends only on (seed, pixel, sample), not on the camera or the frame, so static
// content renders bit-identically in every frame and the result never depends on the threads.
RenderedView render_view(const Scene& scene, const PinholeCamera& camera, double t, const RenderSettings& settings);

}  // namespace s4d::synth
