// A storage buffer created holding a copy of host values, or zeros: the one-liners every upload
// site and every fresh accumulator need.
#pragma once
#include <span>
#include <string>
#include <vector>

#include "s4d/engine/buffer.h"
#include "s4d/engine/context.h"
#include "s4d/engine/recorder.h"

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

// `floats` zeros (a buffer of one float when `floats` is 0: Vulkan has no empty buffers), filled on
// the device.
inline Buffer zeroed_buffer(Context& ctx, const std::string& name, size_t floats) {
  Buffer b(ctx, name, (floats > 0 ? floats : 1) * 4);
  Recorder rec(ctx, "zero " + name);
  rec.fill(b, 0);
  ctx.run(std::move(rec));
  return b;
}

}  // namespace s4d::engine
