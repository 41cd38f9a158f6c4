#include "s4d/optim/grad_add.h"

#include <stdexcept>
#include <string>

#include "s4d/primitives/shader_pipeline.h"
#include "s4d_optim.h"

namespace s4d::optim {

void record_grad_add(engine::Recorder& rec, const engine::Buffer& dst, const engine::Buffer& src, uint32_t n) {
  for (const engine::Buffer* b : {&dst, &src})
    if (b->size() < size_t{n} * 4)
      throw std::invalid_argument("grad_add: buffer '" + b->name() + "' holds fewer than " + std::to_string(n) + " floats");
  const gpu::AddParams p{.n = n, ._pad0 = 0, ._pad1 = 0, ._pad2 = 0};
  rec.dispatch(primitives::shader_pipeline(rec.context(), shaders::Id::grad_add),
               {S4D_BIND(ADD_DST, dst), S4D_BIND(ADD_SRC, src)}, p, primitives::ceil_div(n, S4D_ADD_WG));
}

}  // namespace s4d::optim
