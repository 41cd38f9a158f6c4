#include "s4d/metrics/clipiqa.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "s4d/metrics/rgb_tensor.h"

namespace s4d::metrics {

namespace {

std::vector<double> unit(const std::vector<double>& v, const char* what) {
  double norm = 0;
  for (double x : v) norm += x * x;
  norm = std::sqrt(norm);
  if (!(norm > 0)) throw std::invalid_argument(std::string("clipiqa+: the ") + what + " feature is zero");
  std::vector<double> out(v.size());
  for (size_t i = 0; i < v.size(); ++i) out[i] = v[i] / norm;
  return out;
}

double dot(const std::vector<double>& a, const std::vector<double>& b) {
  double s = 0;
  for (size_t i = 0; i < a.size(); ++i) s += a[i] * b[i];
  return s;
}

}  // namespace

double clipiqa_score(const std::vector<double>& image_feature, const std::vector<double>& good,
                     const std::vector<double>& bad, double logit_scale) {
  if (good.size() != image_feature.size() || bad.size() != image_feature.size())
    throw std::invalid_argument("clipiqa+: image feature of " + std::to_string(image_feature.size()) +
                                " values against text features of " + std::to_string(good.size()) + " and " +
                                std::to_string(bad.size()));
  const std::vector<double> f = unit(image_feature, "image");
  const double good_logit = logit_scale * dot(f, unit(good, "good prompt's"));
  const double bad_logit = logit_scale * dot(f, unit(bad, "bad prompt's"));
  // softmax over the pair, [0]: 1 / (1 + exp(bad - good)).
  return 1.0 / (1.0 + std::exp(bad_logit - good_logit));
}

ClipIqaPlus::ClipIqaPlus(engine::Context& ctx, const io::SafetensorsFile& weights) : ctx_(ctx), net_(ctx, weights) {
  const uint32_t d = net_.output_dim();
  const std::vector<float> text = weights.read("text_features", {2, d});
  good_.assign(text.begin(), text.begin() + d);
  bad_.assign(text.begin() + d, text.end());
  logit_scale_ = std::exp(double(weights.read("logit_scale", {}).at(0)));
}

double ClipIqaPlus::operator()(const io::ImageF& rgb) const {
  const std::vector<float> f = net_.features(upload_rgb(ctx_, rgb, normalisation(kClipMean, kClipStd), "clipiqa+"));
  return clipiqa_score(std::vector<double>(f.begin(), f.end()), good_, bad_, logit_scale_);
}

}  // namespace s4d::metrics
