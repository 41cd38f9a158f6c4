// Exact optical flow from the renderer: the rasterizer knows where every Gaussian is, so the flow of
// a pixel between two frames is the alpha-weighted mean of the screen displacements of the Gaussians
// blended into it. Each Gaussian's mean is projected in both frames (camera and time may both
// change; flow_project), the difference becomes its colour (du, dv, 0) (flow_displace) and the
// rasterizer blends those colours exactly as it blends RGB; dividing by the accumulated alpha gives
// the weighted mean. Kernels in shaders/flow, CPU twin in training/ref/include/s4d/ref/flow_ref.h.
//
// Convention (the warp loss's, bench/metrics/include/s4d/metrics/flow.h): flow(x) takes pixel x of
// the frame it is rendered in to x + flow(x) in the other frame; u to the right, v down, pixels.
#pragma once
#include <cstdint>
#include <vector>

#include "s4d/engine/buffer.h"
#include "s4d/engine/context.h"
#include "s4d/splat/rasterizer.h"

namespace s4d::splat {

// Writes the screen lanes of g's means seen from `cam` into `screen`: [N*3] floats (u, v, valid),
// layout S4D_FLOW_SCREEN_* in shaders/shared/s4d_flow.h; valid = 0 behind the near plane. Waits.
// Throws std::invalid_argument naming the buffer when `screen` or the means are too small.
void project_means(engine::Context& ctx, const GaussianParams& g, const Camera& cam, engine::Buffer& screen);

// Writes colours[3i..3i+2] = (du, dv, 0) = to - from for each of n Gaussians, 0 where either lane set
// marks it invalid. Waits. Throws std::invalid_argument naming a buffer that is too small.
void screen_displacement(engine::Context& ctx, const engine::Buffer& from, const engine::Buffer& to, uint32_t n,
                         engine::Buffer& colors);

struct FlowImage {
  uint32_t width = 0, height = 0;
  std::vector<float> u, v;  // [H*W] row-major, pixels
};

// Renders g (its colours replaced by `displacement`, [N*3] from screen_displacement) from `cam` and
// divides by the accumulated alpha; 0 where nothing was blended (alpha <= 1e-6, as the expected
// depth). The rasterizer's outputs are overwritten.
FlowImage render_flow(Rasterizer& r, GaussianParams g, const engine::Buffer& displacement, const Camera& cam);

}  // namespace s4d::splat
