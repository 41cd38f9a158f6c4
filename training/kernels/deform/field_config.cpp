#include "s4d/deform/field_config.h"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace s4d::deform {

namespace {

void require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("deformation field: " + what);
}

}  // namespace

gpu::DeformShape deform_shape(const FieldConfig& c) {
  const char* axes = "xyzt";
  for (int k = 0; k < 4; ++k)
    require(c.resolution[k] >= S4D_DEFORM_MIN_RESOLUTION,
            std::string("resolution.") + axes[k] + " is " + std::to_string(c.resolution[k]) + ", needs >= " +
                std::to_string(S4D_DEFORM_MIN_RESOLUTION));
  require(!c.multires.empty() && c.multires.size() <= S4D_DEFORM_MAX_LEVELS,
          "multires has " + std::to_string(c.multires.size()) + " levels, needs 1.." + std::to_string(S4D_DEFORM_MAX_LEVELS));
  for (uint32_t m : c.multires) require(m >= 1, "multires entries must be >= 1");
  require(c.channels >= 1 && c.channels <= S4D_DEFORM_MAX_CHANNELS,
          "channels is " + std::to_string(c.channels) + ", needs 1.." + std::to_string(S4D_DEFORM_MAX_CHANNELS));
  require(c.channels * c.multires.size() <= S4D_DEFORM_MAX_FEAT,
          "channels x levels is " + std::to_string(c.channels * c.multires.size()) + ", needs <= " +
              std::to_string(S4D_DEFORM_MAX_FEAT));
  require(c.width >= 1 && c.width <= S4D_DEFORM_MAX_WIDTH,
          "width is " + std::to_string(c.width) + ", needs 1.." + std::to_string(S4D_DEFORM_MAX_WIDTH));
  require(c.trunk_extra <= S4D_DEFORM_MAX_TRUNK_EXTRA,
          "trunk_extra is " + std::to_string(c.trunk_extra) + ", needs <= " + std::to_string(S4D_DEFORM_MAX_TRUNK_EXTRA));
  require(c.heads != 0 && c.heads < (1u << S4D_DEFORM_HEADS), "heads must be a non-empty set of S4D_DEFORM_HEAD_* bits");
  for (int k = 0; k < 3; ++k)
    require(c.aabb_max[k] > c.aabb_min[k], std::string("aabb_max.") + axes[k] + " must exceed aabb_min." + axes[k]);
  require(std::isfinite(c.time_range[0]) && std::isfinite(c.time_range[1]) && c.time_range[1] > c.time_range[0],
          "time_range must be two finite times, the second larger");

  gpu::DeformShape s{};
  s.resolution = {c.resolution[0], c.resolution[1], c.resolution[2], c.resolution[3]};
  uint32_t m[4] = {1, 1, 1, 1};
  for (size_t l = 0; l < c.multires.size(); ++l) m[l] = c.multires[l];
  s.multires = {m[0], m[1], m[2], m[3]};
  s.levels = static_cast<uint32_t>(c.multires.size());
  s.channels = c.channels;
  s.width = c.width;
  s.trunk_extra = c.trunk_extra;
  s.heads = c.heads;
  // The kernels index planes with 32-bit offsets.
  uint64_t floats = 0;
  for (uint32_t l = 0; l < s.levels; ++l)
    for (uint32_t p = 0; p < S4D_DEFORM_PLANES; ++p) {
      uint64_t plane = c.channels;
      for (uint32_t axis : {S4D_DEFORM_PLANE_AXIS_U(p), S4D_DEFORM_PLANE_AXIS_V(p)})
        plane *= axis == S4D_DEFORM_TIME_AXIS ? uint64_t{c.resolution[3]} : uint64_t{c.resolution[axis]} * m[l];
      floats += plane;
    }
  require(floats < std::numeric_limits<uint32_t>::max(), "planes hold " + std::to_string(floats) + " floats, over 32-bit indexing");
  return s;
}

std::array<float, 3> aabb_scale(const FieldConfig& c) {
  std::array<float, 3> s{};
  for (int k = 0; k < 3; ++k) s[k] = 2.0f / (c.aabb_min[k] - c.aabb_max[k]);
  return s;
}

float grid_time(const FieldConfig& c, double t) {
  return static_cast<float>((2.0 * t - (double(c.time_range[0]) + c.time_range[1])) / (double(c.time_range[1]) - c.time_range[0]));
}

}  // namespace s4d::deform
