// Growth for clouds far below their budget. graphdeco's fixed gradient threshold assumes a start from
// a dense point cloud; a capture that starts from a few random points loses most of them to the
// first prune (empty space fades to transparent) and then grows by a third per densification, so a
// short schedule ends with hundreds of Gaussians (a D-NeRF-like object: 885 of a 15,000 budget,
// 20.5 dB). While a cloud holds less than a quarter of its budget, each densification lowers the
// threshold (never raises it) to the gradient quantile that lets the cloud reach the budget in the
// densifications left; from a quarter on, graphdeco's threshold alone decides.
#pragma once
#include <cstdint>
#include <vector>

#include "s4d/engine/context.h"
#include "s4d/model/trainable_gaussians.h"

namespace s4d::densify {

// The growth factor per densification that takes `count` to `budget` in `events_left` steps, as the
// share of Gaussians that must densify (clone or split adds one each): in [0, 1]; 0 at a quarter of
// the budget or more, or with no event left.
double growth_share(uint32_t count, uint32_t budget, uint32_t events_left);

// The largest threshold at which at least `share` of the seen Gaussians (count > 0) have a mean
// gradient (accum / count) at or above it, capped at `threshold`; `threshold` when share is 0 or
// nothing was seen.
float threshold_for_share(const std::vector<float>& accum, const std::vector<float>& count, double share, float threshold);

// Both, on the cloud's statistics (read back from the device).
float growth_threshold(engine::Context& ctx, const model::TrainableGaussians& g, float threshold, uint32_t budget,
                       uint32_t events_left);

}  // namespace s4d::densify
