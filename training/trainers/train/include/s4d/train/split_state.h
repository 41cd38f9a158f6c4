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

// The state with its SH (and their Adam moments) cut to `degree`'s coefficients, each Gaussian's
// first ones kept. Throws std::invalid_argument for a degree above the stored one or below 0.
model::HostState with_sh_degree(const model::HostState& s, int degree);

}  // namespace s4d::train
