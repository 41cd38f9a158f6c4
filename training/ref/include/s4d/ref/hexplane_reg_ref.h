// CPU twin of deform_reg: the HexPlane regularisers of 4DGaussians' fine stage (ALGORITHMS.md 3.2),
//   R = w_plane_tv      * sum_levels sum_{xy, xz, yz} smooth(P)
//     + w_time_smooth   * sum_levels sum_{xt, yt, zt} smooth(P)
//     + w_l1_time       * sum_levels sum_{xt, yt, zt} mean |1 - P|,
// smooth(P) = mean over [C, R_v - 2, R_u] of (P[v + 2] - 2 P[v + 1] + P[v])^2 (second difference
// along the plane's height axis). The gradient of |1 - P| at P = 1 is 0, as PyTorch's abs.
// Templated on the scalar type.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "s4d_deform.h"

namespace s4d::ref {

struct RegWeights {
  double plane_tv = 0, time_smoothness = 0, l1_time = 0;
};

// R for `planes`; adds dR/d planes to v_planes when it is non-null.
template <class T>
T hexplane_regularisers(const gpu::DeformShape& s, const std::vector<T>& planes, const RegWeights& w,
                        std::vector<T>* v_planes) {
  T total = 0;
  const size_t C = s.channels;
  for (uint32_t l = 0; l < s.levels; ++l)
    for (uint32_t p = 0; p < S4D_DEFORM_PLANES; ++p) {
      const bool time_plane = S4D_DEFORM_PLANE_AXIS_V(p) == S4D_DEFORM_TIME_AXIS;
      const size_t ru = gpu::deform_axis_res(s, l, S4D_DEFORM_PLANE_AXIS_U(p));
      const size_t rv = gpu::deform_axis_res(s, l, S4D_DEFORM_PLANE_AXIS_V(p));
      const size_t base = gpu::deform_plane_offset(s, l, p), row = ru * C;
      const T smooth_weight = T(time_plane ? w.time_smoothness : w.plane_tv) / T((rv - 2) * row);
      for (size_t v = 0; v + 2 < rv; ++v)
        for (size_t e = 0; e < row; ++e) {
          const size_t i = base + v * row + e;
          const T d = planes[i + 2 * row] - 2 * planes[i + row] + planes[i];
          total += smooth_weight * d * d;
          if (v_planes == nullptr) continue;
          const T g = 2 * smooth_weight * d;
          (*v_planes)[i] += g, (*v_planes)[i + row] -= 2 * g, (*v_planes)[i + 2 * row] += g;
        }
      if (!time_plane) continue;
      const T l1_weight = T(w.l1_time) / T(rv * row);
      for (size_t i = base; i < base + rv * row; ++i) {
        const T r = T(1) - planes[i];
        total += l1_weight * (r < T(0) ? -r : r);
        if (v_planes != nullptr) (*v_planes)[i] -= l1_weight * T(r > T(0) ? 1 : r < T(0) ? -1 : 0);
      }
    }
  return total;
}

}  // namespace s4d::ref
