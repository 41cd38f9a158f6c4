// A host-side training state of n Gaussians at SH degree `degree` with every array filled by seeded
// uniform values in [-1, 1]: what checkpoint and reorder tests write, read back and compare.
#pragma once
#include <cstddef>
#include <random>
#include <vector>

#include "s4d/model/trainable_gaussians.h"

namespace s4d::test {

inline model::HostState small_state(size_t n, int degree, unsigned seed) {
  model::HostState s;
  s.cloud.sh_degree = degree;
  const size_t k = size_t((degree + 1) * (degree + 1));
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1, 1);
  auto fill = [&](std::vector<float>& v, size_t count) {
    v.resize(count);
    for (float& x : v) x = u(rng);
  };
  fill(s.cloud.means, n * 3), fill(s.cloud.log_scales, n * 3), fill(s.cloud.quats, n * 4), fill(s.cloud.opacity_logits, n);
  fill(s.cloud.sh, n * k * 3);
  for (splat::Attr a : splat::kCloudAttrs) {
    const size_t width = splat::attr_floats(a, static_cast<uint32_t>(k));
    fill(s.m[a], n * width), fill(s.v[a], n * width);
  }
  for (auto& st : s.stats) fill(st, n);
  return s;
}

}  // namespace s4d::test
