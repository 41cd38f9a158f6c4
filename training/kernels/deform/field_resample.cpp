#include "s4d/deform/field_resample.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace s4d::deform {

namespace {

// The texel coordinate on an axis of `r` texels of grid coordinate g, clamped to the border.
double texel_of(double g, uint32_t r) { return std::clamp((g + 1.0) * 0.5 * (r - 1), 0.0, double(r - 1)); }

// Where texel i of axis `axis` (of `to`, r texels) lies on the same axis of `from`, as a texel
// coordinate of `from` (rf texels). Space goes through both boxes (grid = (x - max) * scale - 1),
// time through both time ranges (grid_time).
double old_texel(const FieldConfig& from, const FieldConfig& to, uint32_t axis, uint32_t i, uint32_t r, uint32_t rf) {
  const double g = 2.0 * i / (r - 1) - 1.0;
  if (axis == S4D_DEFORM_TIME_AXIS) {
    const double t = to.time_range[0] + (g + 1.0) * 0.5 * (double(to.time_range[1]) - to.time_range[0]);
    return texel_of((2.0 * t - (double(from.time_range[0]) + from.time_range[1])) / (double(from.time_range[1]) - from.time_range[0]), rf);
  }
  const double x = to.aabb_max[axis] + (g + 1.0) * 0.5 * (double(to.aabb_min[axis]) - to.aabb_max[axis]);
  const double g_from = (x - from.aabb_max[axis]) * 2.0 / (double(from.aabb_min[axis]) - from.aabb_max[axis]) - 1.0;
  return texel_of(g_from, rf);
}

}  // namespace

std::vector<float> resample_planes(const FieldConfig& from, const FieldConfig& to, std::span<const float> planes) {
  const gpu::DeformShape sf = deform_shape(from), st = deform_shape(to);
  if (sf.levels != st.levels)
    throw std::invalid_argument("resample_planes: multires has " + std::to_string(st.levels) + " levels, the trained field " +
                                std::to_string(sf.levels));
  if (sf.channels != st.channels)
    throw std::invalid_argument("resample_planes: channels is " + std::to_string(st.channels) + ", the trained field's " +
                                std::to_string(sf.channels));
  if (planes.size() != gpu::deform_planes_total(sf))
    throw std::invalid_argument("resample_planes: planes hold " + std::to_string(planes.size()) + " floats, the field " +
                                std::to_string(gpu::deform_planes_total(sf)));
  const uint32_t C = st.channels;
  std::vector<float> out(gpu::deform_planes_total(st));
  for (uint32_t l = 0; l < st.levels; ++l)
    for (uint32_t p = 0; p < S4D_DEFORM_PLANES; ++p) {
      const uint32_t au = S4D_DEFORM_PLANE_AXIS_U(p), av = S4D_DEFORM_PLANE_AXIS_V(p);
      const uint32_t ru = gpu::deform_axis_res(st, l, au), rv = gpu::deform_axis_res(st, l, av);
      const uint32_t fu = gpu::deform_axis_res(sf, l, au), fv = gpu::deform_axis_res(sf, l, av);
      const float* src = planes.data() + gpu::deform_plane_offset(sf, l, p);
      float* dst = out.data() + gpu::deform_plane_offset(st, l, p);
      for (uint32_t j = 0; j < rv; ++j) {
        const double tv = old_texel(from, to, av, j, rv, fv);
        const uint32_t y0 = std::min(static_cast<uint32_t>(tv), fv - 2);
        const double wy = tv - y0;
        for (uint32_t i = 0; i < ru; ++i) {
          const double tu = old_texel(from, to, au, i, ru, fu);
          const uint32_t x0 = std::min(static_cast<uint32_t>(tu), fu - 2);
          const double wx = tu - x0;
          const float* t00 = src + (size_t{y0} * fu + x0) * C;
          const float* t01 = t00 + size_t{fu} * C;
          for (uint32_t c = 0; c < C; ++c) {
            const double top = (1 - wx) * t00[c] + wx * t00[C + c], bottom = (1 - wx) * t01[c] + wx * t01[C + c];
            dst[(size_t{j} * ru + i) * C + c] = static_cast<float>((1 - wy) * top + wy * bottom);
          }
        }
      }
    }
  return out;
}

}  // namespace s4d::deform
