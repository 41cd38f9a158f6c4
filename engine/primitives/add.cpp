#include "s4d/primitives/add.h"

#include <stdexcept>
#include <string>

#include "s4d/primitives/shader_pipeline.h"
#include "s4d_optim.h"  // AddParams, S4D_ADD_WG (the kernel lives in shaders/optim)

namespace s4d::primitives {

void cmd_add(engine::Recorder& rec, const engine::Buffer& dst, const engine::Buffer& src, uint32_t n) {
  for (const engine::Buffer* b : {&dst, &src})
    if (b->size() < size_t{n} * 4)
      throw std::invalid_argument("grad_add: buffer '" + b->name() + "' holds fewer than " + std::to_string(n) + " floats");
  const gpu::AddParams p{.n = n, ._pad0 = 0, ._pad1 = 0, ._pad2 = 0};
  rec.dispatch(primitives::shader_pipeline(rec.context(), shaders::Id::grad_add),
               {S4D_BIND(ADD_DST, dst), S4D_BIND(ADD_SRC, src)}, p, primitives::ceil_div(n, S4D_ADD_WG));
}

}  // namespace s4d::primitives
