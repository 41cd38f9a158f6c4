#include "s4d/deform/field_init.h"

#include <cmath>
#include <random>

namespace s4d::deform {

namespace {

// Uniform in [lo, hi) from the top 24 bits of a 32-bit Mersenne twister draw.
float uniform(std::mt19937& rng, double lo, double hi) {
  return static_cast<float>(lo + (hi - lo) * static_cast<double>(rng() >> 8) * 0x1p-24);
}

void init_linear(std::vector<float>& mlp, uint32_t offset, uint32_t in, uint32_t out, std::mt19937& rng) {
  const double xavier = std::sqrt(6.0 / (in + out)), bias = 1.0 / std::sqrt(double(in));
  for (uint32_t k = 0; k < out * in; ++k) mlp[offset + k] = uniform(rng, -xavier, xavier);
  for (uint32_t k = 0; k < out; ++k) mlp[offset + out * in + k] = uniform(rng, -bias, bias);
}

}  // namespace

std::vector<float> initial_planes(const gpu::DeformShape& s, uint32_t seed) {
  std::mt19937 rng(seed);
  std::vector<float> planes(gpu::deform_planes_total(s));
  for (uint32_t l = 0; l < s.levels; ++l)
    for (uint32_t p = 0; p < S4D_DEFORM_PLANES; ++p) {
      const uint32_t begin = gpu::deform_plane_offset(s, l, p), end = begin + gpu::deform_plane_floats(s, l, p);
      const bool time_plane = S4D_DEFORM_PLANE_AXIS_V(p) == S4D_DEFORM_TIME_AXIS;
      for (uint32_t k = begin; k < end; ++k) planes[k] = time_plane ? 1.0f : uniform(rng, 0.1, 0.5);
    }
  return planes;
}

std::vector<float> initial_mlp(const gpu::DeformShape& s, uint32_t seed) {
  std::mt19937 rng(seed ^ 0x9E3779B9u);  // a stream apart from the planes'
  std::vector<float> mlp(gpu::deform_mlp_total(s));
  const uint32_t W = s.width;
  init_linear(mlp, gpu::deform_trunk_offset(s, 0), gpu::deform_feat_dim(s), W, rng);
  for (uint32_t e = 1; e <= s.trunk_extra; ++e) init_linear(mlp, gpu::deform_trunk_offset(s, e), W, W, rng);
  for (uint32_t h = 0; h < S4D_DEFORM_HEADS; ++h) {
    if (!gpu::deform_head_on(s, h)) continue;
    const uint32_t o1 = gpu::deform_head_offset(s, h);
    init_linear(mlp, o1, W, W, rng);
    init_linear(mlp, o1 + gpu::deform_linear_floats(W, W), W, gpu::deform_head_out(h), rng);
  }
  return mlp;
}

}  // namespace s4d::deform
