#include "s4d/metrics/lpips.h"

#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>

#include "s4d/metrics/rgb_tensor.h"

namespace s4d::metrics {

void normalise_channels(util::Chw<double>& f) {
  const size_t plane = size_t{f.h} * f.w;
  for (size_t p = 0; p < plane; ++p) {
    double sum = 0;
    for (size_t c = 0; c < f.c; ++c) sum += f.v[c * plane + p] * f.v[c * plane + p];
    const double inv = 1.0 / (std::sqrt(sum) + kLpipsEps);
    for (size_t c = 0; c < f.c; ++c) f.v[c * plane + p] *= inv;
  }
}

double lpips_head(const LpipsFeatures& a, const LpipsFeatures& b, const std::vector<std::vector<double>>& lin) {
  if (a.size() != lin.size() || b.size() != lin.size())
    throw std::invalid_argument("lpips: " + std::to_string(a.size()) + " and " + std::to_string(b.size()) +
                                " taps for " + std::to_string(lin.size()) + " heads");
  double total = 0;
  for (size_t l = 0; l < lin.size(); ++l) {
    const util::Chw<double>& x = a[l];
    const util::Chw<double>& y = b[l];
    if (x.c != y.c || x.h != y.h || x.w != y.w || x.c != lin[l].size())
      throw std::invalid_argument("lpips: tap " + std::to_string(l) + " shapes differ (images of different sizes?)");
    const size_t plane = size_t{x.h} * x.w;
    double sum = 0;
    for (size_t c = 0; c < x.c; ++c) {
      double s = 0;
      for (size_t p = 0; p < plane; ++p) {
        const double d = x.v[c * plane + p] - y.v[c * plane + p];
        s += d * d;
      }
      sum += lin[l][c] * s;
    }
    total += sum / double(plane);
  }
  return total;
}

Lpips::Lpips(engine::Context& ctx, const io::SafetensorsFile& backbone, const io::SafetensorsFile& heads, LpipsNet net,
             const std::optional<std::array<uint32_t, 5>>& widths, LpipsInput input)
    : ctx_(ctx), net_(net), input_(input) {
  std::vector<uint32_t> channels;
  if (net == LpipsNet::vgg) {
    nn::VggWidths w;
    if (widths) w.level = *widths;
    vgg_ = std::make_unique<nn::TorchVgg>(ctx, backbone, nn::TorchVggDepth::vgg16,
                                          std::vector<int>(kLpipsVggTaps.begin(), kLpipsVggTaps.end()), w);
    for (size_t l = 0; l < vgg_->tap_count(); ++l) channels.push_back(vgg_->tap_channels(l));
  } else {
    nn::AlexWidths w;
    if (widths) w.level = *widths;
    alex_ = std::make_unique<nn::TorchAlexNet>(ctx, backbone, w);
    for (size_t l = 0; l < alex_->tap_count(); ++l) channels.push_back(alex_->tap_channels(l));
  }
  for (size_t l = 0; l < channels.size(); ++l) {
    const std::vector<float> w = heads.read("lin" + std::to_string(l) + ".model.1.weight", {1, int64_t{channels[l]}, 1, 1});
    lin_.emplace_back(w.begin(), w.end());
  }
}

LpipsFeatures Lpips::features(const io::ImageF& rgb) const {
  // [0, 1] -> 2x - 1 (signed_unit) -> (x - shift) / scale, one affine map per channel.
  const bool pm1 = input_ == LpipsInput::signed_unit;
  ChannelAffine map;
  for (int c = 0; c < 3; ++c) {
    map.mul[c] = (pm1 ? 2.0f : 1.0f) / kLpipsScale[c];
    map.add[c] = ((pm1 ? -1.0f : 0.0f) - kLpipsShift[c]) / kLpipsScale[c];
  }
  const nn::Tensor x = upload_rgb(ctx_, rgb, map, "lpips");
  engine::Recorder rec(ctx_, vgg_ ? "lpips vgg16" : "lpips alexnet");
  const std::vector<nn::Tensor> taps = vgg_ ? vgg_->features(rec, x) : alex_->features(rec, x);
  ctx_.run(std::move(rec));
  LpipsFeatures out;
  for (const nn::Tensor& t : taps) {
    out.push_back(download_double(ctx_, t));
    normalise_channels(out.back());
  }
  return out;
}

}  // namespace s4d::metrics
