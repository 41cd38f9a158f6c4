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

// LayerNorm(channels): "<prefix>.weight" and "<prefix>.bias", [channels] each.
NormWeights load_norm(engine::Context& ctx, const io::SafetensorsFile& file, const std::string& prefix, uint32_t channels);

}  // namespace s4d::nn
