// A device tensor: one image's float [C, H, W] in a storage buffer (layouts: shaders/shared/s4d_nn.h).
#pragma once
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "s4d/engine/buffer.h"
#include "s4d/engine/context.h"

namespace s4d::nn {

struct Tensor {
  engine::Buffer buffer;
  uint32_t c = 0, h = 0, w = 0;

  size_t plane() const { return size_t{h} * w; }
  size_t count() const { return c * plane(); }
  std::string shape() const;  // "[c, h, w]"
};

// An uninitialised tensor. The buffer is named "<name> [c, h, w]", so a tensor over the device's
// storage-buffer range fails with std::invalid_argument naming it, its shape and the limit.
Tensor make_tensor(engine::Context& ctx, const std::string& name, uint32_t c, uint32_t h, uint32_t w);

// A tensor holding `values` ([c, h, w]); throws std::invalid_argument when the count differs.
Tensor upload_tensor(engine::Context& ctx, const std::string& name, uint32_t c, uint32_t h, uint32_t w,
                     std::span<const float> values);

// The tensor's values, after all work submitted so far.
std::vector<float> download(engine::Context& ctx, const Tensor& t);

}  // namespace s4d::nn
