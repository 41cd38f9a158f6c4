#include "s4d/optim/grad_mask.h"

#include <stdexcept>
#include <string>

#include "s4d/primitives/shader_pipeline.h"
#include "s4d_optim.h"

namespace s4d::optim {

void record_grad_mask(engine::Recorder& rec, const engine::Buffer& values, const engine::Buffer& mask, uint32_t rows,
                      uint32_t row) {
  const uint64_t n = uint64_t{rows} * row;
  if (row == 0 || n > UINT32_MAX) throw std::invalid_argument("grad_mask: row length must be positive and rows x row fit 32 bits");
  if (values.size() < n * 4) throw std::invalid_argument("grad_mask: buffer '" + values.name() + "' holds fewer than " + std::to_string(n) + " floats");
  if (mask.size() < size_t{rows} * 4) throw std::invalid_argument("grad_mask: mask '" + mask.name() + "' holds fewer than " + std::to_string(rows) + " entries");
  const gpu::MaskParams p{.n = static_cast<uint32_t>(n), .row = row, ._pad0 = 0, ._pad1 = 0};
  rec.dispatch(primitives::shader_pipeline(rec.context(), shaders::Id::grad_mask),
               {S4D_BIND(MASK_VALUES, values), S4D_BIND(MASK_ROWS, mask)}, p, primitives::ceil_div(p.n, S4D_MASK_WG));
}

}  // namespace s4d::optim
