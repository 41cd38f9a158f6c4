// CPU twin of the exact-flow kernels (shaders/flow): flow_project puts each Gaussian's mean on
// screen in one frame, flow_displace turns two frames' screen positions into the per-Gaussian colour
// (du, dv, 0) that the rasterizer blends into a flow image. Templated on the scalar type.
#pragma once
#include <cmath>
#include <cstddef>
#include <vector>

#include "s4d/ref/splat_project_ref.h"
#include "s4d_flow.h"

namespace s4d::ref {

// [N, 3] lanes (u, v, valid): the pinhole projection of every mean, valid = 1 when the mean is in
// front of the near plane and projects to finite pixels; (0, 0, 0) otherwise.
template <class T>
std::vector<T> flow_project(const std::vector<T>& means, const Camera<T>& cam) {
  const size_t n = means.size() / 3;
  std::vector<T> screen(n * S4D_FLOW_SCREEN_STRIDE, T(0));
  const auto& V = cam.world_to_cam;
  for (size_t i = 0; i < n; ++i) {
    const T* m = &means[3 * i];
    T t[3];
    for (int r = 0; r < 3; ++r) t[r] = V[4 * r] * m[0] + V[4 * r + 1] * m[1] + V[4 * r + 2] * m[2] + V[4 * r + 3];
    const T u = cam.fx * t[0] / t[2] + cam.cx, v = cam.fy * t[1] / t[2] + cam.cy;
    if (!(t[2] > T(kNearZ)) || !std::isfinite(u) || !std::isfinite(v)) continue;
    T* s = &screen[S4D_FLOW_SCREEN_STRIDE * i];
    s[S4D_FLOW_SCREEN_U] = u;
    s[S4D_FLOW_SCREEN_V] = v;
    s[S4D_FLOW_SCREEN_VALID] = T(1);
  }
  return screen;
}

// [N, 3] colours (du, dv, 0) = to - from, 0 where either frame's lane is not valid.
template <class T>
std::vector<T> flow_displace(const std::vector<T>& from, const std::vector<T>& to) {
  const size_t n = from.size() / S4D_FLOW_SCREEN_STRIDE;
  std::vector<T> colors(n * 3, T(0));
  for (size_t i = 0; i < n; ++i) {
    const T* a = &from[S4D_FLOW_SCREEN_STRIDE * i];
    const T* b = &to[S4D_FLOW_SCREEN_STRIDE * i];
    if (!(a[S4D_FLOW_SCREEN_VALID] > T(0.5) && b[S4D_FLOW_SCREEN_VALID] > T(0.5))) continue;
    colors[3 * i] = b[S4D_FLOW_SCREEN_U] - a[S4D_FLOW_SCREEN_U];
    colors[3 * i + 1] = b[S4D_FLOW_SCREEN_V] - a[S4D_FLOW_SCREEN_V];
  }
  return colors;
}

}  // namespace s4d::ref
