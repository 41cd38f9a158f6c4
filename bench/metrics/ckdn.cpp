#include "s4d/metrics/ckdn.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "s4d/metrics/rgb_tensor.h"
#include "s4d/metrics/torch_resize.h"

namespace s4d::metrics {

namespace {

// PIL's bicubic (Keys, a = -0.5), which torch's antialiased bicubic uses.
double cubic(double x) {
  constexpr double a = -0.5;
  x = std::abs(x);
  if (x < 1.0) return ((a + 2.0) * x - (a + 3.0)) * x * x + 1.0;
  if (x < 2.0) return (((x - 5.0) * x + 8.0) * x - 4.0) * a;
  return 0.0;
}

// One output index's taps along an axis: the first input index and the normalised weights.
struct Taps {
  int first = 0;
  std::vector<double> weights;
};

std::vector<Taps> bicubic_taps(int in, int out) {
  // torch's _compute_index_ranges_weights (align_corners=False, scale = in / out): support 2 per
  // unit of the output grid, stretched by the scale when shrinking so the filter antialiases.
  const double scale = double(in) / double(out);
  const double support = scale >= 1.0 ? 2.0 * scale : 2.0;
  const double inv = scale >= 1.0 ? 1.0 / scale : 1.0;
  std::vector<Taps> taps(static_cast<size_t>(out));
  for (int i = 0; i < out; ++i) {
    const double center = scale * (i + 0.5);
    const int lo = std::max(int(center - support + 0.5), 0);
    const int hi = std::min(int(center + support + 0.5), in);
    Taps& t = taps[size_t(i)];
    t.first = lo;
    double total = 0.0;
    for (int j = lo; j < hi; ++j) total += t.weights.emplace_back(cubic((j - center + 0.5) * inv));
    for (double& w : t.weights) w /= total;
  }
  return taps;
}

}  // namespace

io::ImageF resize_shorter_side(const io::ImageF& image, int shorter, ResizeFilter filter) {
  if (image.width <= 0 || image.height <= 0 || image.channels <= 0)
    throw std::invalid_argument("resize_shorter_side: empty image");
  if (shorter <= 0) throw std::invalid_argument("resize_shorter_side: size " + std::to_string(shorter) + " is not positive");
  const bool wide = image.width >= image.height;
  const int short_side = wide ? image.height : image.width, long_side = wide ? image.width : image.height;
  const int long_out = int(double(int64_t{shorter} * long_side) / double(short_side));
  const int out_w = wide ? long_out : shorter, out_h = wide ? shorter : long_out;
  if (out_w == image.width && out_h == image.height) return image;
  const int c = image.channels;
  io::ImageF out{out_w, out_h, c, std::vector<float>(size_t(out_w) * size_t(out_h) * size_t(c))};
  if (filter == ResizeFilter::nearest) {
    const std::vector<int> sx = torch_nearest_index(image.width, out_w), sy = torch_nearest_index(image.height, out_h);
    for (int y = 0; y < out_h; ++y)
      for (int x = 0; x < out_w; ++x)
        for (int k = 0; k < c; ++k)
          out.data[(size_t(y) * out_w + x) * c + k] = image.data[(size_t(sy[size_t(y)]) * image.width + sx[size_t(x)]) * c + k];
    return out;
  }
  // Separable: rows to the new width, then columns to the new height (double throughout).
  const std::vector<Taps> tx = bicubic_taps(image.width, out_w), ty = bicubic_taps(image.height, out_h);
  std::vector<double> rows(size_t(image.height) * out_w * c, 0.0);
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < out_w; ++x) {
      const Taps& t = tx[size_t(x)];
      for (size_t j = 0; j < t.weights.size(); ++j)
        for (int k = 0; k < c; ++k)
          rows[(size_t(y) * out_w + x) * c + k] +=
              t.weights[j] * image.data[(size_t(y) * image.width + t.first + int(j)) * c + k];
    }
  for (int y = 0; y < out_h; ++y) {
    const Taps& t = ty[size_t(y)];
    for (int x = 0; x < out_w; ++x)
      for (int k = 0; k < c; ++k) {
        double v = 0.0;
        for (size_t j = 0; j < t.weights.size(); ++j) v += t.weights[j] * rows[((t.first + j) * out_w + x) * c + k];
        out.data[(size_t(y) * out_w + x) * c + k] = float(v);
      }
  }
  return out;
}

io::ImageF center_crop(const io::ImageF& image, int size) {
  if (image.width < size || image.height < size)
    throw std::invalid_argument("center_crop: image " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                                " is smaller than " + std::to_string(size) + "x" + std::to_string(size));
  const int top = int(std::nearbyint((image.height - size) / 2.0)), left = int(std::nearbyint((image.width - size) / 2.0));
  const int c = image.channels;
  io::ImageF out{size, size, c, std::vector<float>(size_t(size) * size * c)};
  for (int y = 0; y < size; ++y)
    std::copy_n(image.data.begin() + std::ptrdiff_t((size_t(top + y) * image.width + left) * c), size_t(size) * c,
                out.data.begin() + std::ptrdiff_t(size_t(y) * size * c));
  return out;
}

Ckdn::Ckdn(engine::Context& ctx, const io::SafetensorsFile& weights) : ctx_(ctx), net_(ctx, weights) {}

double Ckdn::operator()(const io::ImageF& restored, const io::ImageF& reference) const {
  const ChannelAffine imagenet = normalisation(kImagenetMean, kImagenetStd);
  const nn::Tensor x = upload_rgb(
      ctx_, center_crop(resize_shorter_side(restored, kCkdnResize, ResizeFilter::bicubic_antialias), kCkdnCrop), imagenet, "ckdn");
  const nn::Tensor y =
      upload_rgb(ctx_, center_crop(resize_shorter_side(reference, kCkdnResize, ResizeFilter::nearest), kCkdnCrop), imagenet, "ckdn");
  engine::Recorder rec(ctx_, "ckdn");
  const nn::Tensor logit = net_.logit(rec, x, y);
  ctx_.run(std::move(rec));
  return 1.0 / (1.0 + std::exp(-double(nn::download(ctx_, logit).at(0))));
}

}  // namespace s4d::metrics
