// The cached pipeline of an embedded shader variant.
#pragma once
#include "s4d/engine/context.h"
#include "s4d/engine/pipeline.h"
#include "s4d/shader_registry.h"

namespace s4d::primitives {

inline const engine::Pipeline& shader_pipeline(engine::Context& ctx, shaders::Id id) {
  const shaders::Entry& e = shaders::get(id);
  return ctx.pipeline(e.name, e.spirv());
}

inline uint32_t ceil_div(uint64_t a, uint64_t b) { return static_cast<uint32_t>((a + b - 1) / b); }

}  // namespace s4d::primitives
