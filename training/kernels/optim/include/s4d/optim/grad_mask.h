// Zeroes the rows of a per-Gaussian array whose mask entry is 0 (shaders/optim/grad_mask.comp):
// stage 4 trains only the Gaussians of a selected region.
#pragma once
#include <cstdint>

#include "s4d/engine/buffer.h"
#include "s4d/engine/recorder.h"

namespace s4d::optim {

// values: [rows * row] floats; mask: [rows] u32. Throws std::invalid_argument naming a buffer that
// is too small or a zero row length.
void record_grad_mask(engine::Recorder& rec, const engine::Buffer& values, const engine::Buffer& mask, uint32_t rows,
                      uint32_t row);

}  // namespace s4d::optim
