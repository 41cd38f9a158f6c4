#include "s4d/train/split_state.h"

#include <stdexcept>
#include <string>

#include "s4d/deform/motion_split.h"

namespace s4d::train {

model::HostState gather_state(const model::HostState& s, std::span<const uint32_t> order) {
  const size_t n = s.cloud.size();
  if (order.size() != n)
    throw std::invalid_argument("gather_state: an order of " + std::to_string(order.size()) + " for " +
                                std::to_string(n) + " Gaussians");
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

}  // namespace s4d::train
