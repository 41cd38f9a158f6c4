// The learned metrics' host <-> device tensors: an RGB frame (io::ImageF [H, W, 3]) as a network
// input [3, H, W] on the device, each channel mapped to (v * mul[c] + add[c]) (LPIPS's [-1, 1] +
// scaling layer, ImageNet normalisation, applied on the host before the upload), and a network's
// output back as a double tensor for the heads computed on the host.
#pragma once
#include <array>
#include <string>

#include "s4d/engine/context.h"
#include "s4d/io/image_io.h"
#include "s4d/nn/tensor.h"
#include "s4d/util/chw.h"

namespace s4d::metrics {

// torchvision's ImageNet normalisation (VGG inputs of DISTS and the Gram loss's torchvision VGG19).
inline constexpr std::array<float, 3> kImagenetMean = {0.485f, 0.456f, 0.406f};
inline constexpr std::array<float, 3> kImagenetStd = {0.229f, 0.224f, 0.225f};

struct ChannelAffine {
  std::array<float, 3> mul{1.0f, 1.0f, 1.0f}, add{0.0f, 0.0f, 0.0f};
};

// (v - mean[c]) / std[c] as an affine map.
ChannelAffine normalisation(const std::array<float, 3>& mean, const std::array<float, 3>& std);

// Throws std::invalid_argument naming `metric` when the image is not RGB.
nn::Tensor upload_rgb(engine::Context& ctx, const io::ImageF& image, const ChannelAffine& map, const std::string& metric);

// The tensor's values (after all work submitted so far) as double.
util::Chw<double> download_double(engine::Context& ctx, const nn::Tensor& t);

}  // namespace s4d::metrics
