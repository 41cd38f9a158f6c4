// A storage buffer created holding a copy of host values: the one-liner every upload site needs.
#pragma once
#include <span>
#include <string>
#include <vector>

#include "s4d/engine/buffer.h"
#include "s4d/engine/context.h"

namespace s4d::engine {

template <class T>
Buffer buffer_from(Context& ctx, const std::string& name, std::span<const T> values) {
  Buffer b(ctx, name, values.size_bytes());
  if (!values.empty()) ctx.upload(b, values);
  return b;
}

template <class T>
Buffer buffer_from(Context& ctx, const std::string& name, const std::vector<T>& values) {
  return buffer_from(ctx, name, std::span<const T>(values));
}

}  // namespace s4d::engine
