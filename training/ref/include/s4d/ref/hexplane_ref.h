// CPU twin of the HexPlane lookup of deform_feat / deform_feat_bwd (ALGORITHMS.md 3.1): a point's feature
// vector (6 bilinear samples multiplied per level, levels concatenated) and its backward to the
// point's xyz and to the plane texels. Layouts and the coordinate mapping are documented in
// shaders/shared/s4d_deform.h. Templated on the scalar type (float, double).
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "s4d_deform.h"

namespace s4d::ref {

// The whole deformation field: HexPlane and MLP parameters.
template <class T>
struct DeformField {
  gpu::DeformShape shape{};
  std::array<T, 3> aabb_max{};    // 4DGaussians' aabb[0]
  std::array<T, 3> aabb_scale{};  // 2 / (aabb_min - aabb_max)
  std::vector<T> planes;          // gpu::deform_planes_total(shape) floats
  std::vector<T> mlp;             // gpu::deform_mlp_total(shape) floats
};

namespace detail {

// One plane's bilinear footprint: texel (x0, y0) and its right / lower neighbours.
template <class T>
struct Bilinear {
  size_t base = 0;            // float index of texel (x0, y0), channel 0
  size_t step_x = 0, step_y = 0;
  T wx{}, wy{};               // weights of the x0 + 1 and y0 + 1 texels
  T dix_du{}, diy_dv{};       // d texel coordinate / d grid coordinate; 0 where the border clamps
};

// Texel coordinate of grid coordinate g on an axis of r texels (align_corners = True, border
// clamp), its cell and the weight of the cell's upper texel. Like PyTorch, the clamp's gradient is 0
// on the border itself.
template <class T>
void texel_coord(T g, uint32_t r, uint32_t& cell, T& w, T& d_dg) {
  const T max_index = T(r - 1);
  const T i = (g + T(1)) * T(0.5) * max_index;
  d_dg = i > T(0) && i < max_index ? T(0.5) * max_index : T(0);
  const T c = std::clamp(i, T(0), max_index);
  cell = std::min(static_cast<uint32_t>(std::floor(c)), r - 2);
  w = c - T(cell);
}

template <class T>
Bilinear<T> bilinear(const gpu::DeformShape& s, uint32_t level, uint32_t plane, const std::array<T, 4>& g) {
  const uint32_t au = S4D_DEFORM_PLANE_AXIS_U(plane), av = S4D_DEFORM_PLANE_AXIS_V(plane);
  const uint32_t ru = gpu::deform_axis_res(s, level, au), rv = gpu::deform_axis_res(s, level, av);
  Bilinear<T> b;
  uint32_t x0 = 0, y0 = 0;
  texel_coord(g[au], ru, x0, b.wx, b.dix_du);
  texel_coord(g[av], rv, y0, b.wy, b.diy_dv);
  b.step_x = s.channels;
  b.step_y = size_t{ru} * s.channels;
  b.base = gpu::deform_plane_offset(s, level, plane) + y0 * b.step_y + x0 * b.step_x;
  return b;
}

template <class T>
T bilinear_value(const std::vector<T>& planes, const Bilinear<T>& b, uint32_t c) {
  const size_t i = b.base + c;
  const T top = (T(1) - b.wx) * planes[i] + b.wx * planes[i + b.step_x];
  const T bottom = (T(1) - b.wx) * planes[i + b.step_y] + b.wx * planes[i + b.step_y + b.step_x];
  return (T(1) - b.wy) * top + b.wy * bottom;
}

}  // namespace detail

// Grid coordinates of a point: xyz through the (mirrored) AABB, time unnormalised.
template <class T>
std::array<T, 4> hexplane_coords(const DeformField<T>& f, const T* xyz, T time) {
  std::array<T, 4> g{};
  for (int k = 0; k < 3; ++k) g[k] = (xyz[k] - f.aabb_max[k]) * f.aabb_scale[k] - T(1);
  g[3] = time;
  return g;
}

// Feature vector of a point, [C * levels].
template <class T>
std::vector<T> hexplane_features(const DeformField<T>& f, const T* xyz, T time) {
  const gpu::DeformShape& s = f.shape;
  const std::array<T, 4> g = hexplane_coords(f, xyz, time);
  std::vector<T> feat(gpu::deform_feat_dim(s), T(1));
  for (uint32_t l = 0; l < s.levels; ++l)
    for (uint32_t p = 0; p < S4D_DEFORM_PLANES; ++p) {
      const detail::Bilinear<T> b = detail::bilinear(s, l, p, g);
      for (uint32_t c = 0; c < s.channels; ++c) feat[l * s.channels + c] *= detail::bilinear_value(f.planes, b, c);
    }
  return feat;
}

// Backward of hexplane_features for cotangent v_feat: adds dL/d xyz to v_xyz[0..2] and dL/d texel
// to v_planes (same layout as f.planes).
template <class T>
void hexplane_features_bwd(const DeformField<T>& f, const T* xyz, T time, const std::vector<T>& v_feat, T* v_xyz,
                           std::vector<T>& v_planes) {
  const gpu::DeformShape& s = f.shape;
  const std::array<T, 4> g = hexplane_coords(f, xyz, time);
  const uint32_t C = s.channels;
  for (uint32_t l = 0; l < s.levels; ++l) {
    std::array<detail::Bilinear<T>, S4D_DEFORM_PLANES> b;
    std::vector<T> sample(S4D_DEFORM_PLANES * C);
    for (uint32_t p = 0; p < S4D_DEFORM_PLANES; ++p) {
      b[p] = detail::bilinear(s, l, p, g);
      for (uint32_t c = 0; c < C; ++c) sample[p * C + c] = detail::bilinear_value(f.planes, b[p], c);
    }
    for (uint32_t p = 0; p < S4D_DEFORM_PLANES; ++p) {
      const detail::Bilinear<T>& bp = b[p];
      const uint32_t au = S4D_DEFORM_PLANE_AXIS_U(p), av = S4D_DEFORM_PLANE_AXIS_V(p);
      T v_ix = 0, v_iy = 0;
      for (uint32_t c = 0; c < C; ++c) {
        T others = v_feat[l * C + c];  // dL/d sample = v_feat * product of the other five samples
        for (uint32_t q = 0; q < S4D_DEFORM_PLANES; ++q)
          if (q != p) others *= sample[q * C + c];
        const size_t i = bp.base + c;
        v_planes[i] += (T(1) - bp.wx) * (T(1) - bp.wy) * others;
        v_planes[i + bp.step_x] += bp.wx * (T(1) - bp.wy) * others;
        v_planes[i + bp.step_y] += (T(1) - bp.wx) * bp.wy * others;
        v_planes[i + bp.step_y + bp.step_x] += bp.wx * bp.wy * others;
        const T v00 = f.planes[i], v10 = f.planes[i + bp.step_x], v01 = f.planes[i + bp.step_y],
                v11 = f.planes[i + bp.step_y + bp.step_x];
        v_ix += others * ((T(1) - bp.wy) * (v10 - v00) + bp.wy * (v11 - v01));
        v_iy += others * ((T(1) - bp.wx) * (v01 - v00) + bp.wx * (v11 - v10));
      }
      // The time axis carries no gradient: time is an input, not a parameter.
      if (au < 3) v_xyz[au] += v_ix * bp.dix_du * f.aabb_scale[au];
      if (av < 3) v_xyz[av] += v_iy * bp.diy_dv * f.aabb_scale[av];
    }
  }
}

}  // namespace s4d::ref
