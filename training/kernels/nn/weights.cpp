#include "s4d/nn/weights.h"

#include <cmath>
#include <stdexcept>
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

ConvWeights load_conv_bn(engine::Context& ctx, const io::SafetensorsFile& file, const std::string& conv,
                         const std::string& bn, uint32_t cin, uint32_t cout, uint32_t k) {
  constexpr double kBatchNormEps = 1e-5;  // torch.nn.BatchNorm2d's default, which CKDN and CLIP keep
  std::vector<float> weight = file.read(conv + ".weight", {cout, cin, k, k});
  const std::vector<float> gamma = file.read(bn + ".weight", {cout});
  const std::vector<float> beta = file.read(bn + ".bias", {cout});
  const std::vector<float> mean = file.read(bn + ".running_mean", {cout});
  const std::vector<float> var = file.read(bn + ".running_var", {cout});
  std::vector<float> bias(cout);
  const size_t per_out = size_t{cin} * k * k;
  for (uint32_t o = 0; o < cout; ++o) {
    if (!(var[o] >= 0))
      throw std::runtime_error(file.path().string() + ": " + bn + ".running_var[" + std::to_string(o) + "] is negative");
    const double scale = double(gamma[o]) / std::sqrt(double(var[o]) + kBatchNormEps);
    for (size_t i = 0; i < per_out; ++i) weight[o * per_out + i] = float(double(weight[o * per_out + i]) * scale);
    bias[o] = float(double(beta[o]) - double(mean[o]) * scale);
  }
  return upload_conv(ctx, file.path().filename().string() + " " + conv, cin, cout, k, weight, bias);
}

ConvWeights load_conv_no_bias(engine::Context& ctx, const io::SafetensorsFile& file, const std::string& prefix,
                              uint32_t cin, uint32_t cout, uint32_t k) {
  const std::vector<float> weight = file.read(prefix + ".weight", {cout, cin, k, k});
  return upload_conv(ctx, file.path().filename().string() + " " + prefix, cin, cout, k, weight,
                     std::vector<float>(cout, 0.0f));
}

NormWeights load_norm(engine::Context& ctx, const io::SafetensorsFile& file, const std::string& prefix, uint32_t channels) {
  return upload_norm(ctx, file.path().filename().string() + " " + prefix, channels, file.read(prefix + ".weight", {channels}),
                     file.read(prefix + ".bias", {channels}));
}

}  // namespace s4d::nn
