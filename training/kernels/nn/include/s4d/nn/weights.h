// Layer parameters from safetensors files that keep PyTorch's state-dict names.
#pragma once
#include <cstdint>
#include <string>

#include "s4d/engine/context.h"
#include "s4d/io/safetensors.h"
#include "s4d/nn/layers.h"

namespace s4d::nn {

// Conv2d(cin, cout, k): "<prefix>.weight" [cout, cin, k, k] and "<prefix>.bias" [cout]. Throws
// std::runtime_error naming the file and the tensor when one is missing, wrongly shaped, of
// another dtype or not finite.
ConvWeights load_conv(engine::Context& ctx, const io::SafetensorsFile& file, const std::string& prefix, uint32_t cin,
                      uint32_t cout, uint32_t k);

// Linear(in, out): "<prefix>.weight" [out, in] and "<prefix>.bias" [out], as a 1x1 convolution.
ConvWeights load_linear(engine::Context& ctx, const io::SafetensorsFile& file, const std::string& prefix, uint32_t in,
                        uint32_t out);

// Conv2d(cin, cout, k, bias=False) "<conv>.weight" followed by BatchNorm2d "<bn>.{weight, bias,
// running_mean, running_var}" in eval mode (eps 1e-5, PyTorch's default), folded into one convolution
// with bias: w' = w gamma / sqrt(var + eps) per output channel, b' = beta - mean gamma / sqrt(var + eps)
// (in double, then float). Throws std::runtime_error also when a running variance is negative.
ConvWeights load_conv_bn(engine::Context& ctx, const io::SafetensorsFile& file, const std::string& conv,
                         const std::string& bn, uint32_t cin, uint32_t cout, uint32_t k);

// Conv2d(cin, cout, k, bias=False): "<prefix>.weight" [cout, cin, k, k], a zero bias.
ConvWeights load_conv_no_bias(engine::Context& ctx, const io::SafetensorsFile& file, const std::string& prefix,
                              uint32_t cin, uint32_t cout, uint32_t k);

// LayerNorm(channels): "<prefix>.weight" and "<prefix>.bias", [channels] each.
NormWeights load_norm(engine::Context& ctx, const io::SafetensorsFile& file, const std::string& prefix, uint32_t channels);

}  // namespace s4d::nn
