#include "s4d/metrics/gram_loss.h"

#include <stdexcept>
#include <string>

#include "s4d/metrics/rgb_tensor.h"

namespace s4d::metrics {

std::vector<double> gram_matrix(const std::vector<float>& features, uint32_t channels, size_t positions) {
  if (features.size() != size_t{channels} * positions)
    throw std::invalid_argument("gram_matrix: " + std::to_string(features.size()) + " values for " +
                                std::to_string(channels) + " x " + std::to_string(positions));
  std::vector<double> f(features.begin(), features.end()), g(size_t{channels} * channels);
  const double norm = 1.0 / (double(channels) * double(positions));
  for (size_t i = 0; i < channels; ++i)
    for (size_t j = i; j < channels; ++j) {
      const double* a = f.data() + i * positions;
      const double* b = f.data() + j * positions;
      double s = 0;
      for (size_t p = 0; p < positions; ++p) s += a[p] * b[p];
      g[i * channels + j] = g[j * channels + i] = s * norm;
    }
  return g;
}

double gram_loss(const GramSet& a, const GramSet& b) {
  if (a.channels != b.channels) throw std::invalid_argument("gram_loss: the two images' layer widths differ");
  double total = 0;
  for (size_t l = 0; l < a.g.size(); ++l) {
    double s = 0;
    for (size_t k = 0; k < a.g[l].size(); ++k) s += (a.g[l][k] - b.g[l][k]) * (a.g[l][k] - b.g[l][k]);
    total += s / double(a.g[l].size());
  }
  return total;
}

GramStyleLoss::GramStyleLoss(engine::Context& ctx, const io::SafetensorsFile& vgg19, GramBackbone backbone,
                             const nn::VggWidths& widths)
    : ctx_(ctx), backbone_(backbone) {
  if (backbone == GramBackbone::vgg_normalised)
    normalised_ = std::make_unique<nn::VggEncoder>(ctx, vgg19, 5, widths);
  else
    torchvision_ = std::make_unique<nn::TorchVgg>(ctx, vgg19, nn::TorchVggDepth::vgg19,
                                                  std::vector<int>(kGramVgg19Taps.begin(), kGramVgg19Taps.end()), widths);
}

GramSet GramStyleLoss::grams(const io::ImageF& rgb) const {
  // vgg_normalised's first 1x1 convolution does its own preprocessing from [0, 1] RGB.
  const ChannelAffine map = backbone_ == GramBackbone::vgg_normalised ? ChannelAffine{}
                                                                      : normalisation(kImagenetMean, kImagenetStd);
  const nn::Tensor x = upload_rgb(ctx_, rgb, map, "style_loss_gram");
  engine::Recorder rec(ctx_, "style_loss_gram vgg19");
  const std::vector<nn::Tensor> taps = normalised_ ? normalised_->encode_all(rec, x) : torchvision_->features(rec, x);
  ctx_.run(std::move(rec));
  GramSet out;
  for (const nn::Tensor& t : taps) {
    out.channels.push_back(t.c);
    out.g.push_back(gram_matrix(nn::download(ctx_, t), t.c, t.plane()));
  }
  return out;
}

}  // namespace s4d::metrics
