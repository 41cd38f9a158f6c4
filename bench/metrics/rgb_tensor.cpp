#include "s4d/metrics/rgb_tensor.h"

#include <vector>

#include "s4d/metrics/image_checks.h"

namespace s4d::metrics {

ChannelAffine normalisation(const std::array<float, 3>& mean, const std::array<float, 3>& std) {
  ChannelAffine m;
  for (int c = 0; c < 3; ++c) {
    m.mul[c] = 1.0f / std[c];
    m.add[c] = -mean[c] / std[c];
  }
  return m;
}

nn::Tensor upload_rgb(engine::Context& ctx, const io::ImageF& image, const ChannelAffine& map, const std::string& metric) {
  require_rgb(image, metric, "the image");
  const size_t plane = size_t(image.width) * size_t(image.height);
  std::vector<float> chw(3 * plane);
  for (size_t i = 0; i < plane; ++i)
    for (size_t c = 0; c < 3; ++c) chw[c * plane + i] = image.data[3 * i + c] * map.mul[c] + map.add[c];
  return nn::upload_tensor(ctx, metric + " input", 3, uint32_t(image.height), uint32_t(image.width), chw);
}

util::Chw<double> download_double(engine::Context& ctx, const nn::Tensor& t) {
  util::Chw<double> out(t.c, t.h, t.w);
  const std::vector<float> v = nn::download(ctx, t);
  out.v.assign(v.begin(), v.end());
  return out;
}

}  // namespace s4d::metrics
