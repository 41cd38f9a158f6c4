#include "s4d/metrics/warp_loss.h"

#include <cmath>
#include <limits>
#include <stdexcept>

#include "s4d/metrics/image_checks.h"

namespace s4d::metrics {

namespace {

void require_flow(const Flow& f, int w, int h, const char* what) {
  if (f.width != w || f.height != h || f.uv.size() != size_t(w) * size_t(h) * 2)
    throw std::invalid_argument(std::string("warp_loss: the ") + what + " flow is " + std::to_string(f.width) + "x" +
                                std::to_string(f.height) + ", expected " + std::to_string(w) + "x" + std::to_string(h));
}

// Resample2d of `data` ([H, W, C]) at x + flow(x), into `out`.
void resample(const float* data, int w, int h, int channels, const Flow& flow, float* out) {
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x;
      const double xf = x + double(flow.uv[i * 2]), yf = y + double(flow.uv[i * 2 + 1]);
      const double fx = std::floor(xf), fy = std::floor(yf), a = xf - fx, b = yf - fy;
      auto clamp = [](double v, int n) { return v < 0 ? 0 : (v > n - 1 ? n - 1 : int(v)); };
      const int xl = clamp(fx, w), xr = clamp(fx + 1, w), yt = clamp(fy, h), yb = clamp(fy + 1, h);
      for (int c = 0; c < channels; ++c) {
        auto at = [&](int xx, int yy) { return double(data[(size_t(yy) * w + xx) * channels + c]); };
        out[i * channels + c] = float((1 - a) * (1 - b) * at(xl, yt) + a * (1 - b) * at(xr, yt) +
                                      (1 - a) * b * at(xl, yb) + a * b * at(xr, yb));
      }
    }
}

}  // namespace

io::ImageF warp_back(const io::ImageF& image, const Flow& flow) {
  require_flow(flow, image.width, image.height, "warp");
  io::ImageF out{image.width, image.height, image.channels, std::vector<float>(image.data.size())};
  resample(image.data.data(), image.width, image.height, image.channels, flow, out.data.data());
  return out;
}

std::vector<uint8_t> occlusion_mask(const Flow& forward, const Flow& backward) {
  const int w = forward.width, h = forward.height;
  require_flow(forward, w, h, "forward");
  require_flow(backward, w, h, "backward");
  std::vector<float> bw_at(forward.uv.size());
  resample(backward.uv.data(), w, h, 2, forward, bw_at.data());
  std::vector<uint8_t> mask(size_t(w) * size_t(h));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x;
      const double fu = forward.uv[i * 2], fv = forward.uv[i * 2 + 1], bu = bw_at[i * 2], bv = bw_at[i * 2 + 1];
      const double f2 = fu * fu + fv * fv, b2 = bu * bu + bv * bv;
      const bool inconsistent = (fu + bu) * (fu + bu) + (fv + bv) * (fv + bv) > 0.01 * (f2 + b2) + 0.5;
      double grad = 0;
      for (int c = 0; c < 2; ++c) {
        const double p = forward.uv[i * 2 + c];
        const double dx = x + 1 < w ? p - forward.uv[(i + 1) * 2 + c] : 0.0;
        const double dy = y + 1 < h ? p - forward.uv[(i + size_t(w)) * 2 + c] : 0.0;
        grad += dx * dx + dy * dy;
      }
      mask[i] = inconsistent || grad > 0.01 * f2 + 0.002;
    }
  return mask;
}

PairWarpError warp_error(const io::ImageF& frame_t, const io::ImageF& frame_t1, const Flow& forward,
                         const Flow& backward, WarpNorm norm) {
  require_same_rgb(frame_t, frame_t1, "warp_loss");
  const std::vector<uint8_t> occluded = occlusion_mask(forward, backward);
  require_flow(forward, frame_t.width, frame_t.height, "forward");
  const io::ImageF warped = warp_back(frame_t1, forward);
  double sum = 0;
  size_t valid = 0;
  for (size_t i = 0; i < occluded.size(); ++i) {
    if (occluded[i]) continue;
    ++valid;
    for (int c = 0; c < 3; ++c) {
      const double d = double(warped.data[i * 3 + c]) - double(frame_t.data[i * 3 + c]);
      sum += norm == WarpNorm::abs ? std::abs(d) : d * d;
    }
  }
  // No pixel to compare is no evidence of consistency: NaN, never the perfect 0 that dividing the empty
  // sum by all pixels (Lai's fallback) would give.
  if (valid == 0) return {std::numeric_limits<double>::quiet_NaN(), 0.0};
  return {sum / (3.0 * double(valid)), double(valid) / double(occluded.size())};
}

}  // namespace s4d::metrics
