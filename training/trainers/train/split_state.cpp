#include "s4d/train/split_state.h"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

#include "s4d/deform/motion_split.h"

namespace s4d::train {

namespace {

// Row j of each array holds Gaussian order[j]; order's rows are below the cloud's size.
model::HostState gather_state_rows(const model::HostState& s, std::span<const uint32_t> order) {
  const size_t n = s.cloud.size();
  auto gather = [&](const std::vector<float>& values) {
    return deform::gather_rows<float>(values, order, n == 0 ? 0 : values.size() / n);
  };
  model::HostState out;
  out.cloud.sh_degree = s.cloud.sh_degree;
  const auto from = splat::cloud_arrays(s.cloud);
  const auto to = splat::cloud_arrays(out.cloud);
  for (splat::Attr a : splat::kCloudAttrs) *to[a] = gather(*from[a]), out.m[a] = gather(s.m[a]), out.v[a] = gather(s.v[a]);
  for (size_t k = 0; k < s.stats.size(); ++k) out.stats[k] = gather(s.stats[k]);
  return out;
}

}  // namespace

model::HostState gather_state(const model::HostState& s, std::span<const uint32_t> order) {
  const size_t n = s.cloud.size();
  if (order.size() != n)
    throw std::invalid_argument("gather_state: an order of " + std::to_string(order.size()) + " for " +
                                std::to_string(n) + " Gaussians");
  return gather_state_rows(s, order);
}

model::HostState remove_gaussians(const model::HostState& s, std::span<const uint32_t> removed) {
  const uint32_t n = static_cast<uint32_t>(s.cloud.size());
  std::vector<uint32_t> kept;
  kept.reserve(n);
  size_t next = 0;
  for (uint32_t g = 0; g < n; ++g) {
    if (next < removed.size() && removed[next] == g) {
      ++next;
      continue;
    }
    kept.push_back(g);
  }
  if (next != removed.size())
    throw std::invalid_argument("remove_gaussians: row " + std::to_string(removed[next]) +
                                " is past the cloud's " + std::to_string(n) + " Gaussians or out of order");
  return gather_state_rows(s, kept);
}

model::HostState with_sh_degree(const model::HostState& s, int degree) {
  if (degree < 0 || degree > s.cloud.sh_degree)
    throw std::invalid_argument("with_sh_degree: degree " + std::to_string(degree) + " is not in 0.." +
                                std::to_string(s.cloud.sh_degree));
  const size_t n = s.cloud.size(), from = s.cloud.sh_coeffs() * 3, to = size_t((degree + 1) * (degree + 1)) * 3;
  auto cut = [&](const std::vector<float>& rows) {
    std::vector<float> out(n * to);
    for (size_t g = 0; g < n; ++g)
      std::copy_n(rows.begin() + static_cast<std::ptrdiff_t>(g * from), to, out.begin() + static_cast<std::ptrdiff_t>(g * to));
    return out;
  };
  model::HostState out = s;
  const splat::Attr sh = splat::Attr::sh;
  out.cloud.sh_degree = degree;
  out.cloud.sh = cut(s.cloud.sh), out.m[sh] = cut(s.m[sh]), out.v[sh] = cut(s.v[sh]);
  return out;
}

}  // namespace s4d::train
