// dst += src on the GPU (shaders/optim/grad_add.comp): sums the gradients of a batch's views, and
// adds a style's deltas to a run's colours and opacities.
#pragma once
#include <cstdint>

#include "s4d/engine/buffer.h"
#include "s4d/engine/recorder.h"

namespace s4d::primitives {

// Records the sum of the first n floats; throws std::invalid_argument naming a buffer that holds fewer.
void cmd_add(engine::Recorder& rec, const engine::Buffer& dst, const engine::Buffer& src, uint32_t n);

}  // namespace s4d::primitives
