#include "s4d/nn/group_norm.h"

#include <stdexcept>
#include <string>

#include "s4d/primitives/shader_pipeline.h"
#include "s4d_nn.h"

namespace s4d::nn {

Tensor group_norm_cells(engine::Recorder& rec, const Tensor& x, const NormWeights& w, uint32_t groups, float eps,
                        const CellWindow& cells, bool relu) {
  const auto fail = [&](const std::string& what) { throw std::invalid_argument("group_norm " + w.name + ": " + what); };
  if (x.c != w.channels) fail("expects " + std::to_string(w.channels) + " channels, got " + x.shape());
  if (groups == 0 || x.c % groups != 0) fail(std::to_string(groups) + " groups do not divide " + x.shape());
  if (cells.cell_h == 0 || x.h % cells.cell_h != 0) fail(x.shape() + " is not a stack of " + std::to_string(cells.cell_h) + "-row cells");
  if (cells.rows == 0 || cells.cols == 0 || cells.row0 + cells.rows > cells.cell_h || cells.col0 + cells.cols > x.w)
    fail("window " + std::to_string(cells.rows) + "x" + std::to_string(cells.cols) + " at (" + std::to_string(cells.row0) +
         ", " + std::to_string(cells.col0) + ") leaves a " + std::to_string(cells.cell_h) + "x" + std::to_string(x.w) + " cell");
  // llvmpipe silently ends invocations past 65,535 loop iterations (s4d_nn.h): the write loop is the longest.
  const uint64_t iterations = (uint64_t{x.c / groups} * cells.cell_h * x.w + S4D_NN_STATS_WG - 1) / S4D_NN_STATS_WG;
  if (iterations > S4D_NN_MAX_LOOP) fail("cells of " + std::to_string(iterations) + " values per invocation are too large");
  Tensor y = make_tensor(rec.context(), w.name, x.c, x.h, x.w);
  const gpu::NnGroupNormParams p{.channels = x.c,
                                 .groups = groups,
                                 .height = x.h,
                                 .width = x.w,
                                 .cell_h = cells.cell_h,
                                 .row0 = cells.row0,
                                 .rows = cells.rows,
                                 .col0 = cells.col0,
                                 .cols = cells.cols,
                                 .flags = relu ? S4D_NN_FLAG_RELU : 0u,
                                 .eps = eps,
                                 ._pad0 = 0};
  rec.dispatch(primitives::shader_pipeline(rec.context(), shaders::Id::nn_group_norm),
               {S4D_BIND(GN_IN, x.buffer), S4D_BIND(GN_WEIGHT, w.weight), S4D_BIND(GN_BIAS, w.bias), S4D_BIND(GN_OUT, y.buffer)},
               p, size_t{x.h / cells.cell_h} * groups);
  rec.barrier();
  return y;
}

}  // namespace s4d::nn
