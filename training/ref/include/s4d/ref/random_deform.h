// Seeded random inputs for the deformation field's twin, GPU tests and benchmark: uniform values and
// canonical Gaussians spread over a field's AABB. One generator, so every check draws alike.
#pragma once
#include <array>
#include <cstdint>
#include <random>
#include <type_traits>
#include <vector>

#include "s4d/ref/deform_ref.h"

namespace s4d::ref {

template <class T = float>  // float unless asked: the bounds do not choose the type
std::vector<T> uniform(size_t n, std::mt19937& rng, std::type_identity_t<T> lo, std::type_identity_t<T> hi) {
  std::uniform_real_distribution<T> u(lo, hi);
  std::vector<T> v(n);
  for (T& x : v) x = u(rng);
  return v;
}

struct RandomGaussiansSpec {
  double margin = 0.02;      // means stay this far inside the AABB...
  uint32_t outside_every = 0;  // ...except every k-th Gaussian (index % k == 3), 0.3 outside it; 0: none
  double log_scale_lo = -3, log_scale_hi = -1;
  uint32_t sh_coeffs = 1;  // K per colour channel
};

// Means uniform in [aabb_min + margin, aabb_max - margin], log-scales in the spec's range,
// unnormalised quaternions in [-1, 1]^4, opacity logits in [-2, 2], SH in [-0.5, 0.5]; no still mask.
template <class T>
DeformGaussians<T> random_gaussians(const std::array<float, 3>& aabb_min, const std::array<float, 3>& aabb_max, size_t n,
                                    std::mt19937& rng, const RandomGaussiansSpec& spec = {}) {
  DeformGaussians<T> g;
  for (size_t i = 0; i < n; ++i) {
    const bool outside = spec.outside_every != 0 && i % spec.outside_every == 3;
    const T margin = T(outside ? -0.3 : spec.margin);
    for (int k = 0; k < 3; ++k) g.means.push_back(uniform<T>(1, rng, T(aabb_min[k]) + margin, T(aabb_max[k]) - margin)[0]);
  }
  g.log_scales = uniform<T>(3 * n, rng, T(spec.log_scale_lo), T(spec.log_scale_hi));
  g.quats = uniform<T>(4 * n, rng, -1, 1);
  g.opacity_logits = uniform<T>(n, rng, -2, 2);
  g.sh = uniform<T>(n * 3 * spec.sh_coeffs, rng, T(-0.5), T(0.5));
  return g;
}

}  // namespace s4d::ref
