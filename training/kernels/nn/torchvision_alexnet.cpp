#include "s4d/nn/torchvision_alexnet.h"

#include <stdexcept>
#include <string>

#include "s4d/nn/weights.h"

namespace s4d::nn {

TorchAlexNet::TorchAlexNet(engine::Context& ctx, const io::SafetensorsFile& file, const AlexWidths& widths)
    : widths_(widths) {
  const auto& w = widths.level;
  conv_[0] = load_conv(ctx, file, "features.0", 3, w[0], 11);
  conv_[1] = load_conv(ctx, file, "features.3", w[0], w[1], 5);
  conv_[2] = load_conv(ctx, file, "features.6", w[1], w[2], 3);
  conv_[3] = load_conv(ctx, file, "features.8", w[2], w[3], 3);
  conv_[4] = load_conv(ctx, file, "features.10", w[3], w[4], 3);
}

std::vector<Tensor> TorchAlexNet::features(engine::Recorder& rec, const Tensor& x) const {
  if (x.c != 3) throw std::invalid_argument("TorchAlexNet: expects an RGB image [3, H, W], got " + x.shape());
  if (x.h < kMinSize || x.w < kMinSize)
    throw std::invalid_argument("TorchAlexNet: image " + x.shape() + " is smaller than the " + std::to_string(kMinSize) + "x" +
                                std::to_string(kMinSize) + " its taps need");
  std::vector<Tensor> taps;
  taps.reserve(5);  // each layer reads the previous tap
  taps.push_back(conv_strided(rec, x, conv_[0], 4, 2, true));
  taps.push_back(conv_strided(rec, maxpool3s2(rec, taps[0]), conv_[1], 1, 2, true));
  taps.push_back(conv3x3_zero_pad(rec, maxpool3s2(rec, taps[1]), conv_[2], true));
  taps.push_back(conv3x3_zero_pad(rec, taps[2], conv_[3], true));
  taps.push_back(conv3x3_zero_pad(rec, taps[3], conv_[4], true));
  return taps;
}

}  // namespace s4d::nn
