// Reordering a trainable cloud's host state (deform::MotionSplit's order): every per-Gaussian array
// (parameters, both Adam moments, densification statistics) moves together, so row j of each
// holds Gaussian order[j].
#pragma once
#include <cstdint>
#include <span>

#include "s4d/model/trainable_gaussians.h"

namespace s4d::train {

// Throws std::invalid_argument when `order` does not have one entry per Gaussian.
model::HostState gather_state(const model::HostState& s, std::span<const uint32_t> order);

}  // namespace s4d::train
