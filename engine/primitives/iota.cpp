#include "s4d/primitives/iota.h"

#include <stdexcept>

#include "s4d_primitives.h"
#include "s4d/primitives/shader_pipeline.h"

namespace s4d::primitives {

void cmd_iota(engine::Recorder& rec, const engine::Buffer& out, uint32_t n, uint32_t first) {
  if (out.size() < size_t{n} * 4)
    throw std::invalid_argument("iota: buffer '" + out.name() + "' holds fewer than " + std::to_string(n) + " u32");
  const gpu::IotaParams params{.n = n, .first = first, ._pad0 = 0, ._pad1 = 0};
  rec.dispatch(shader_pipeline(rec.context(), shaders::Id::iota), {S4D_BIND(IOTA_OUT, out)}, params,
               ceil_div(n, S4D_IOTA_WG));
}

}  // namespace s4d::primitives
