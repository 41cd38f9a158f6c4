#include "s4d/metrics/dists.h"

#include <stdexcept>
#include <string>

#include "s4d/metrics/rgb_tensor.h"

namespace s4d::metrics {

double dists_from_features(const DistsFeatures& x, const DistsFeatures& y, const std::vector<double>& alpha,
                           const std::vector<double>& beta) {
  if (x.size() != y.size()) throw std::invalid_argument("dists: the two images have different stage counts");
  double score = 0;
  size_t k = 0;  // channel index over all stages
  for (size_t s = 0; s < x.size(); ++s) {
    const util::Chw<double>& a = x[s];
    const util::Chw<double>& b = y[s];
    if (a.c != b.c || a.h != b.h || a.w != b.w)
      throw std::invalid_argument("dists: stage " + std::to_string(s) + " shapes differ (images of different sizes?)");
    const size_t n = size_t{a.h} * a.w;
    for (size_t c = 0; c < a.c; ++c, ++k) {
      if (k >= alpha.size() || k >= beta.size()) throw std::invalid_argument("dists: more channels than alpha/beta entries");
      const double* p = a.v.data() + c * n;
      const double* q = b.v.data() + c * n;
      double mx = 0, my = 0;
      for (size_t i = 0; i < n; ++i) mx += p[i], my += q[i];
      mx /= double(n);
      my /= double(n);
      double vx = 0, vy = 0, xy = 0;
      for (size_t i = 0; i < n; ++i) {
        vx += (p[i] - mx) * (p[i] - mx);
        vy += (q[i] - my) * (q[i] - my);
        xy += p[i] * q[i];
      }
      vx /= double(n);
      vy /= double(n);
      const double cov = xy / double(n) - mx * my;  // DISTS_pt.py: mean(x y) - mean(x) mean(y)
      const double s1 = (2 * mx * my + kDistsC1) / (mx * mx + my * my + kDistsC1);
      const double s2 = (2 * cov + kDistsC2) / (vx + vy + kDistsC2);
      score += alpha[k] * s1 + beta[k] * s2;
    }
  }
  if (k != alpha.size()) throw std::invalid_argument("dists: alpha/beta have more entries than the stages' channels");
  return 1.0 - score;
}

Dists::Dists(engine::Context& ctx, const io::SafetensorsFile& vgg16, const io::SafetensorsFile& alpha_beta,
             const nn::VggWidths& widths)
    : ctx_(ctx),
      vgg_(ctx, vgg16, nn::TorchVggDepth::vgg16, {kDistsTaps.begin(), kDistsTaps.end()}, widths, nn::TorchVggPool::l2) {
  int64_t total = 3;
  for (size_t t = 0; t < vgg_.tap_count(); ++t) total += vgg_.tap_channels(t);
  const std::vector<float> a = alpha_beta.read("alpha", {1, total, 1, 1});
  const std::vector<float> b = alpha_beta.read("beta", {1, total, 1, 1});
  double sum = 0;
  for (float v : a) sum += v;
  for (float v : b) sum += v;
  if (!(sum > 0))
    throw std::runtime_error(alpha_beta.path().string() + ": alpha and beta sum to " + std::to_string(sum) +
                             "; DISTS divides by that sum, so it must be positive");
  for (float v : a) alpha_.push_back(v / sum);
  for (float v : b) beta_.push_back(v / sum);
}

DistsFeatures Dists::features(const io::ImageF& rgb) const {
  const nn::Tensor x = upload_rgb(ctx_, rgb, normalisation(kImagenetMean, kImagenetStd), "dists");
  engine::Recorder rec(ctx_, "dists vgg16");
  const std::vector<nn::Tensor> taps = vgg_.features(rec, x);
  ctx_.run(std::move(rec));
  DistsFeatures out;
  util::Chw<double> raw(3, uint32_t(rgb.height), uint32_t(rgb.width));  // stage 0: the input itself
  const size_t plane = size_t(rgb.width) * size_t(rgb.height);
  for (size_t i = 0; i < plane; ++i)
    for (size_t c = 0; c < 3; ++c) raw.v[c * plane + i] = rgb.data[3 * i + c];
  out.push_back(std::move(raw));
  for (const nn::Tensor& t : taps) out.push_back(download_double(ctx_, t));
  return out;
}

}  // namespace s4d::metrics
