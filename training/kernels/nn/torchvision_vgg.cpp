#include "s4d/nn/torchvision_vgg.h"

#include <stdexcept>
#include <string>

#include "s4d/nn/weights.h"

namespace s4d::nn {

TorchVgg::TorchVgg(engine::Context& ctx, const io::SafetensorsFile& file, TorchVggDepth depth, std::vector<int> taps,
                   const VggWidths& widths, TorchVggPool pool)
    : pool_(pool) {
  if (taps.empty()) throw std::invalid_argument("TorchVgg: no taps");
  for (size_t i = 1; i < taps.size(); ++i)
    if (taps[i] <= taps[i - 1]) throw std::invalid_argument("TorchVgg: taps must increase");
  // torchvision's cfgs "D" (VGG16) and "E" (VGG19): convolutions per block, a max pool after each.
  const std::array<int, 5> convs = depth == TorchVggDepth::vgg16 ? std::array<int, 5>{2, 2, 3, 3, 3}
                                                                  : std::array<int, 5>{2, 2, 4, 4, 4};
  int index = 0;  // module index in `features`: conv i, its ReLU i + 1, then the next module
  uint32_t cin = 3;
  size_t next_tap = 0;
  int pools = 0;
  for (int block = 0; block < 5 && next_tap < taps.size(); ++block) {
    if (block > 0) {
      steps_.push_back({});
      ++pools;
      ++index;
    }
    for (int c = 0; c < convs[block] && next_tap < taps.size(); ++c) {
      const uint32_t cout = widths.level[block];
      Step s{load_conv(ctx, file, "features." + std::to_string(index), cin, cout, 3), false};
      if (index + 1 == taps[next_tap]) {
        s.tap = true;
        tap_channels_.push_back(cout);
        min_size_ = pool == TorchVggPool::max ? 1u << pools : 1u;
        ++next_tap;
      } else if (index + 1 > taps[next_tap]) {
        throw std::invalid_argument("TorchVgg: tap " + std::to_string(taps[next_tap]) + " is not a ReLU of features");
      }
      steps_.push_back(std::move(s));
      cin = cout;
      index += 2;
    }
  }
  if (next_tap < taps.size())
    throw std::invalid_argument("TorchVgg: tap " + std::to_string(taps[next_tap]) + " is past the last ReLU of features");
}

std::vector<Tensor> TorchVgg::features(engine::Recorder& rec, const Tensor& x) const {
  if (x.c != 3) throw std::invalid_argument("TorchVgg: expects an RGB image [3, H, W], got " + x.shape());
  if (x.h < min_size_ || x.w < min_size_)
    throw std::invalid_argument("TorchVgg: image " + x.shape() + " is smaller than the " + std::to_string(min_size_) +
                                "x" + std::to_string(min_size_) + " its taps need");
  std::vector<Tensor> out;
  out.reserve(tap_channels_.size());  // `cur` may point into it
  Tensor y;
  const Tensor* cur = &x;
  for (const Step& s : steps_) {
    Tensor next = !s.conv.name.empty()         ? conv3x3_zero_pad(rec, *cur, s.conv, true)
                  : pool_ == TorchVggPool::max ? maxpool2_floor(rec, *cur)
                                               : l2pool(rec, *cur);
    if (s.tap) {
      out.push_back(std::move(next));
      cur = &out.back();
    } else {
      y = std::move(next);
      cur = &y;
    }
  }
  return out;
}

}  // namespace s4d::nn
