#include "s4d/metrics/dino_subject.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "s4d/metrics/image_checks.h"
#include "s4d/metrics/rgb_tensor.h"

namespace s4d::metrics {

namespace {

// PyTorch's linear source taps for one axis (upsample_bilinear2d, align_corners False, no scale
// factor): the scale in/out in float, the source coordinate max(scale (dst + 0.5) - 0.5, 0) in
// double, i0 its floor, i1 = i0 + 1 but at the last pixel, weights l = src - i0 and 1 - l in float.
struct LinearTap {
  uint32_t i0, i1;
  float w0, w1;
};

std::vector<LinearTap> linear_taps(uint32_t in, uint32_t out) {
  const double scale = float(in) / float(out);
  std::vector<LinearTap> taps;
  for (uint32_t d = 0; d < out; ++d) {
    const double src = std::max(scale * (d + 0.5) - 0.5, 0.0);
    const auto i0 = static_cast<uint32_t>(src);
    const auto l = static_cast<float>(std::clamp(src - i0, 0.0, 1.0));
    taps.push_back({i0, i0 + 1 < in ? i0 + 1 : i0, 1.0f - l, l});
  }
  return taps;
}

double dot(const std::vector<double>& a, const std::vector<double>& b) {
  double s = 0;
  for (size_t i = 0; i < a.size(); ++i) s += a[i] * b[i];
  return s;
}

}  // namespace

util::Chw<float> dino_transform(const io::ImageF& rgb) {
  require_rgb(rgb, "dino_score", "the frame");
  const auto w = uint32_t(rgb.width), h = uint32_t(rgb.height);
  const uint32_t short_side = std::min(w, h), long_side = std::max(w, h);
  // torchvision: int(size * long / short), a Python float quotient truncated.
  const auto resized_long = static_cast<uint32_t>(double(kDinoShortSide) * double(long_side) / double(short_side));
  const uint32_t out_w = w <= h ? kDinoShortSide : resized_long, out_h = w <= h ? resized_long : kDinoShortSide;
  const std::vector<LinearTap> tx = linear_taps(w, out_w), ty = linear_taps(h, out_h);
  const auto level = [&](uint32_t y, uint32_t x, uint32_t c) {  // the frame as the uint8 VBench reads
    return std::nearbyint(std::clamp(rgb.data[(size_t{y} * w + x) * 3 + c], 0.0f, 1.0f) * 255.0f);
  };
  util::Chw<float> out(3, out_h, out_w);
  for (uint32_t c = 0; c < 3; ++c)
    for (uint32_t y = 0; y < out_h; ++y)
      for (uint32_t x = 0; x < out_w; ++x) {
        const LinearTap& a = ty[y];
        const LinearTap& b = tx[x];
        // PyTorch's order: each neighbour times the product of its two weights, summed in turn (with
        // another order, values within float rounding of a .5 tie round the other way: dino_reference.py).
        const float v = level(a.i0, b.i0, c) * (a.w0 * b.w0) + level(a.i0, b.i1, c) * (a.w0 * b.w1) +
                        level(a.i1, b.i0, c) * (a.w1 * b.w0) + level(a.i1, b.i1, c) * (a.w1 * b.w1);
        // torchvision rounds the resized uint8 image (half to even), then divides by 255.
        out.at(c, y, x) = (std::nearbyint(v) / 255.0f - kImagenetMean[c]) / kImagenetStd[c];
      }
  return out;
}

double subject_pair_score(const std::vector<double>& first, const std::vector<double>& previous,
                          const std::vector<double>& current) {
  if (first.size() != current.size() || previous.size() != current.size())
    throw std::invalid_argument("dino_score: features of different widths");
  return (std::max(0.0, dot(previous, current)) + std::max(0.0, dot(first, current))) / 2;
}

DinoSubject::DinoSubject(engine::Context& ctx, const io::SafetensorsFile& file, uint32_t heads)
    : ctx_(ctx), vit_(ctx, file, heads) {}

std::vector<double> DinoSubject::features(const io::ImageF& rgb) const {
  const util::Chw<float> input = dino_transform(rgb);
  const std::vector<float> cls =
      vit_.cls(nn::upload_tensor(ctx_, "dino_score input", 3, input.h, input.w, input.v));
  std::vector<double> f(cls.begin(), cls.end());
  const double norm = std::sqrt(dot(f, f));
  // F.normalize's eps: a zero feature stays zero (its cosines are then 0).
  for (double& v : f) v /= std::max(norm, 1e-12);
  return f;
}

}  // namespace s4d::metrics
