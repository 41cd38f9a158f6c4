#include "s4d/viewer/adaptive_resolution.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace s4d::viewer {

AdaptiveResolution::AdaptiveResolution(AdaptiveResolutionOptions options) : options_(options) {
  if (!(options_.budget_ms >= 0))
    throw std::invalid_argument("frame budget " + std::to_string(options_.budget_ms) +
                                " ms: expected 0 (always full resolution) or a positive time");
  if (!(options_.settle_ms >= 0))
    throw std::invalid_argument("settle time " + std::to_string(options_.settle_ms) + " ms: expected 0 or more");
  if (!(options_.floor > 0 && options_.floor <= 1))
    throw std::invalid_argument("resolution floor " + std::to_string(options_.floor) + ": expected a scale in (0, 1]");
}

void AdaptiveResolution::measured(double ms, double scale) {
  if (options_.budget_ms == 0 || !(ms > 0) || !(scale > 0)) return;
  const double ratio = moving_scale_ / scale;
  const double predicted = ms * ratio * ratio;
  if (predicted <= options_.budget_ms && predicted >= kLowFraction * options_.budget_ms) return;
  const double wanted = moving_scale_ * std::sqrt(kTargetFraction * options_.budget_ms / predicted);
  const double stepped = std::floor(wanted * kSteps) / kSteps;  // down, so the aim stays under the budget
  moving_scale_ = std::clamp(stepped, options_.floor, 1.0);
}

uint32_t scaled_size(uint32_t size, double scale) {
  return std::max<uint32_t>(1, static_cast<uint32_t>(std::lround(size * scale)));
}

}  // namespace s4d::viewer
