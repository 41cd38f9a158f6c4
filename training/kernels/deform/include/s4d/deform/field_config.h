// Configuration of the 4DGaussians deformation field (ALGORITHMS.md 3.1) and its validated GPU shape.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "s4d_deform.h"

namespace s4d::deform {

struct FieldConfig {
  std::array<uint32_t, 4> resolution{64, 64, 64, 25};  // base (x, y, z, t); time is not multiplied
  std::vector<uint32_t> multires{1, 2};                // spatial multiplier per level
  uint32_t channels = 32;                              // C per plane (kplanes output_coordinate_dim)
  uint32_t width = 64;                                 // W (net_width)
  uint32_t trunk_extra = 0;                            // max(defor_depth - 1, 0) extra ReLU + Linear(W -> W)
  uint32_t heads = S4D_DEFORM_HEADS_DNERF;             // S4D_DEFORM_HEAD_* bits
  std::array<float, 3> aabb_min{-1, -1, -1};           // the initial point cloud's bounds
  std::array<float, 3> aabb_max{1, 1, 1};
  // The times at the time axis's first and last texel. {-1, 1} is 4DGaussians' mapping (the time
  // given to the kernels as the grid coordinate itself), which leaves the half for t < 0 of every
  // time plane unsampled by times in [0, 1]; the presets set {0, 1}.
  std::array<float, 2> time_range{-1, 1};
};

// The shape the kernels see. Throws std::invalid_argument naming the offending field when the
// configuration is outside the kernels' limits (s4d_deform.h) or the AABB is empty.
gpu::DeformShape deform_shape(const FieldConfig& config);

// 2 / (aabb_min - aabb_max) per axis, in float as the kernels receive it.
std::array<float, 3> aabb_scale(const FieldConfig& config);

// The time axis's grid coordinate of time `t` (time_range to [-1, 1]), as the kernels receive it:
// (2t - (lo + hi)) / (hi - lo), which is t itself, bit for bit, for {-1, 1}.
float grid_time(const FieldConfig& config, double t);

}  // namespace s4d::deform
