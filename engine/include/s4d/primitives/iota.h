// out[i] = first + i for i < n (argsort seeds, dispatch-limit tests).
#pragma once
#include <cstdint>

#include "s4d/engine/buffer.h"
#include "s4d/engine/recorder.h"

namespace s4d::primitives {

void cmd_iota(engine::Recorder& rec, const engine::Buffer& out, uint32_t n, uint32_t first = 0);

}  // namespace s4d::primitives
