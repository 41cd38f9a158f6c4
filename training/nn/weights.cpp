#include "s4d/nn/weights.h"

#include <vector>

namespace s4d::nn {

namespace {

ConvWeights load(engine::Context& ctx, const io::SafetensorsFile& file, const std::string& prefix, uint32_t cin,
                 uint32_t cout, uint32_t k, const std::vector<int64_t>& weight_shape) {
  const std::vector<float> weight = file.read(prefix + ".weight", weight_shape);
  const std::vector<float> bias = file.read(prefix + ".bias", {cout});
  return upload_conv(ctx, file.path().filename().string() + " " + prefix, cin, cout, k, weight, bias);
}

}  // namespace

ConvWeights load_conv(engine::Context& ctx, const io::SafetensorsFile& file, const std::string& prefix, uint32_t cin,
                      uint32_t cout, uint32_t k) {
  return load(ctx, file, prefix, cin, cout, k, {cout, cin, k, k});
}

ConvWeights load_linear(engine::Context& ctx, const io::SafetensorsFile& file, const std::string& prefix, uint32_t in,
                        uint32_t out) {
  return load(ctx, file, prefix, in, out, 1, {out, in});
}

NormWeights load_norm(engine::Context& ctx, const io::SafetensorsFile& file, const std::string& prefix, uint32_t channels) {
  return upload_norm(ctx, file.path().filename().string() + " " + prefix, channels, file.read(prefix + ".weight", {channels}),
                     file.read(prefix + ".bias", {channels}));
}

}  // namespace s4d::nn
