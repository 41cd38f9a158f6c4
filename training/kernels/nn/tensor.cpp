#include "s4d/nn/tensor.h"

#include <stdexcept>

#include "s4d/io/safetensors.h"

namespace s4d::nn {

std::string Tensor::shape() const { return io::shape_text({c, h, w}); }

Tensor make_tensor(engine::Context& ctx, const std::string& name, uint32_t c, uint32_t h, uint32_t w) {
  Tensor t;
  t.c = c, t.h = h, t.w = w;
  t.buffer = engine::Buffer(ctx, name + " " + t.shape(), t.count() * sizeof(float));
  return t;
}

Tensor upload_tensor(engine::Context& ctx, const std::string& name, uint32_t c, uint32_t h, uint32_t w,
                     std::span<const float> values) {
  Tensor t = make_tensor(ctx, name, c, h, w);
  if (values.size() != t.count())
    throw std::invalid_argument("tensor '" + name + "' " + t.shape() + ": given " + std::to_string(values.size()) +
                                " values");
  if (!values.empty()) ctx.upload(t.buffer, values);
  return t;
}

std::vector<float> download(engine::Context& ctx, const Tensor& t) { return ctx.download<float>(t.buffer, t.count()); }

}  // namespace s4d::nn
