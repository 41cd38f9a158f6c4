#include "s4d/train/split_state.h"

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

}  // namespace s4d::train
