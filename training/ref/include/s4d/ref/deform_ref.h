// CPU twin of the whole field's kernels (deform_feat + deform_fwd, and deform_bwd + deform_feat_bwd +
// deform_wgrad, the MLP weight gradients): the deformation field applied to canonical Gaussians at time t (ALGORITHMS.md 3.1 "Updates"). Each head's output is
// added to the raw parameter; Gaussians with a non-zero still mask are not deformed and give the
// field no gradient. Templated on the scalar type.
#pragma once
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <vector>

#include "s4d/ref/deform_mlp_ref.h"
#include "s4d/ref/hexplane_ref.h"

namespace s4d::ref {

// Raw Gaussian parameters (flat, as on the GPU) and the still mask (the motion split's).
template <class T>
struct DeformGaussians {
  std::vector<T> means;           // [N, 3]
  std::vector<T> log_scales;      // [N, 3]
  std::vector<T> quats;           // [N, 4] (w, x, y, z)
  std::vector<T> opacity_logits;  // [N]
  std::vector<T> sh;              // [N, K, 3]; K = S4D_DEFORM_SH_COEFFS when the sh head is on
  std::vector<uint32_t> still_mask;  // [N] or empty (nothing still)

  size_t size() const { return opacity_logits.size(); }
  size_t sh_coeffs() const { return size() == 0 ? 0 : sh.size() / (3 * size()); }
  bool is_still(size_t i) const { return !still_mask.empty() && still_mask[i] != 0; }
};

template <class T>
struct DeformGrads {
  DeformGaussians<T> v;   // dL/d canonical parameters (still_mask unused)
  std::vector<T> v_planes;
  std::vector<T> v_mlp;
};

namespace detail {

// The parameter array head h adds to (const or not), and its stride per Gaussian.
template <class G>
auto head_target(G& g, uint32_t h) -> decltype((g.means)) {
  switch (h) {
    case 0: return g.means;
    case 1: return g.log_scales;
    case 2: return g.quats;
    case 3: return g.opacity_logits;
    default: return g.sh;
  }
}

template <class T>
size_t head_stride(const DeformGaussians<T>& g, uint32_t h) {
  return h == 4 ? 3 * g.sh_coeffs() : gpu::deform_head_out(h);
}

template <class T>
void check_deform_inputs(const DeformField<T>& f, const DeformGaussians<T>& g) {
  if (gpu::deform_head_on(f.shape, 4) && g.sh_coeffs() != S4D_DEFORM_SH_COEFFS)
    throw std::invalid_argument("deform twin: the sh head needs 16 SH coefficients per Gaussian");
  if (f.planes.size() != gpu::deform_planes_total(f.shape) || f.mlp.size() != gpu::deform_mlp_total(f.shape))
    throw std::invalid_argument("deform twin: planes or mlp size does not match the shape");
}

}  // namespace detail

// Deformed parameters at `time`. Arrays of heads that are off are copied unchanged.
template <class T>
DeformGaussians<T> deform_forward(const DeformField<T>& f, const DeformGaussians<T>& g, T time) {
  detail::check_deform_inputs(f, g);
  DeformGaussians<T> out = g;
  for (size_t i = 0; i < g.size(); ++i) {
    if (g.is_still(i)) continue;
    const HeadValues<T> d = deform_mlp_forward(f.shape, f.mlp, hexplane_features(f, &g.means[3 * i], time));
    for (uint32_t h = 0; h < S4D_DEFORM_HEADS; ++h)
      for (size_t k = 0; k < d[h].size(); ++k) detail::head_target(out, h)[i * detail::head_stride(g, h) + k] += d[h][k];
  }
  return out;
}

// Backward for cotangents `v_out` of the deformed parameters (same layouts; still_mask unused).
// The raw-parameter gradients pass through (x' = x + delta); the means also get the field's term.
template <class T>
DeformGrads<T> deform_backward(const DeformField<T>& f, const DeformGaussians<T>& g, T time, const DeformGaussians<T>& v_out) {
  detail::check_deform_inputs(f, g);
  DeformGrads<T> r{v_out, std::vector<T>(f.planes.size(), T(0)), std::vector<T>(f.mlp.size(), T(0))};
  r.v.still_mask.clear();
  for (size_t i = 0; i < g.size(); ++i) {
    if (g.is_still(i)) continue;
    HeadValues<T> v_heads;
    for (uint32_t h = 0; h < S4D_DEFORM_HEADS; ++h) {
      if (!gpu::deform_head_on(f.shape, h)) continue;
      const std::vector<T>& src = detail::head_target(v_out, h);
      const size_t base = i * detail::head_stride(g, h);
      v_heads[h].assign(src.begin() + static_cast<std::ptrdiff_t>(base),
                        src.begin() + static_cast<std::ptrdiff_t>(base + gpu::deform_head_out(h)));
    }
    const T* xyz = &g.means[3 * i];
    const std::vector<T> feat = hexplane_features(f, xyz, time);
    const std::vector<T> v_feat = deform_mlp_backward(f.shape, f.mlp, feat, v_heads, r.v_mlp);
    hexplane_features_bwd(f, xyz, time, v_feat, &r.v.means[3 * i], r.v_planes);
  }
  return r;
}

}  // namespace s4d::ref
