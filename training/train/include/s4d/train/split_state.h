// Reordering or thinning a trainable cloud's host state: every per-Gaussian array (parameters, both
// Adam moments, densification statistics) moves together.
#pragma once
#include <cstdint>
#include <span>

#include "s4d/model/trainable_gaussians.h"

namespace s4d::train {

// deform::MotionSplit's order: row j of each array holds Gaussian order[j]. Throws
// std::invalid_argument when `order` does not have one entry per Gaussian.
model::HostState gather_state(const model::HostState& s, std::span<const uint32_t> order);

// The state without the Gaussians in `removed` (ascending), the others in their order. Throws
// std::invalid_argument for a row past the cloud or out of order.
model::HostState remove_gaussians(const model::HostState& s, std::span<const uint32_t> removed);

}  // namespace s4d::train
