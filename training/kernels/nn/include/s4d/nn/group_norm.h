// GroupNorm on a batch of small images stacked along H (kernel nn_group_norm, twin
// ref::group_norm_cells): MUSIQ's patch stem runs its 32x32 patches as one tall tensor whose cells
// hold one patch each, with zero rows and columns between them as padding (musiq_net.h).
#pragma once
#include <cstdint>

#include "s4d/engine/recorder.h"
#include "s4d/nn/layers.h"
#include "s4d/nn/tensor.h"

namespace s4d::nn {

// Each cell is cell_h rows of the tensor; its window rows [row0, row0 + rows) x cols [col0, col0 + cols).
struct CellWindow {
  uint32_t cell_h = 0, row0 = 0, rows = 0, col0 = 0, cols = 0;
};

// GroupNorm(groups, x.c, eps) (weight, bias: `w`) of each cell's window on its own (+ ReLU), zeros
// outside the windows. Throws std::invalid_argument when x.h is not a multiple of cell_h, the window
// leaves the cell, groups do not divide the channels or `w` has another width.
Tensor group_norm_cells(engine::Recorder& rec, const Tensor& x, const NormWeights& w, uint32_t groups, float eps,
                        const CellWindow& cells, bool relu);

}  // namespace s4d::nn
