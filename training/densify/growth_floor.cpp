#include "s4d/densify/growth_floor.h"

#include <algorithm>
#include <cmath>

namespace s4d::densify {

double growth_share(uint32_t count, uint32_t budget, uint32_t events_left) {
  if (events_left == 0 || count == 0 || uint64_t{count} * 4 >= budget) return 0.0;
  const double factor = std::pow(static_cast<double>(budget) / count, 1.0 / events_left);
  return std::clamp(factor - 1.0, 0.0, 1.0);
}

float threshold_for_share(const std::vector<float>& accum, const std::vector<float>& count, double share, float threshold) {
  if (!(share > 0)) return threshold;
  std::vector<float> means;
  for (size_t i = 0; i < accum.size() && i < count.size(); ++i)
    if (count[i] > 0) means.push_back(accum[i] / count[i]);
  if (means.empty()) return threshold;
  // The k-th largest mean: exactly the k largest (and ties) reach it.
  const size_t k = std::clamp<size_t>(static_cast<size_t>(std::ceil(share * static_cast<double>(means.size()))), 1, means.size());
  std::nth_element(means.begin(), means.begin() + static_cast<std::ptrdiff_t>(k - 1), means.end(), std::greater<float>());
  return std::min(threshold, means[k - 1]);
}

float growth_threshold(engine::Context& ctx, const model::TrainableGaussians& g, float threshold, uint32_t budget,
                       uint32_t events_left) {
  const double share = growth_share(static_cast<uint32_t>(g.size()), budget, events_left);
  if (share == 0) return threshold;
  const std::vector<float> accum = ctx.download<float>(g.stat(model::kGradAccum), g.size());
  const std::vector<float> count = ctx.download<float>(g.stat(model::kGradCount), g.size());
  return threshold_for_share(accum, count, share, threshold);
}

}  // namespace s4d::densify
