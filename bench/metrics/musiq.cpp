#include "s4d/metrics/musiq.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "s4d/metrics/image_checks.h"
#include "s4d/metrics/torch_resize.h"

namespace s4d::metrics {

namespace {

constexpr uint32_t kPatch = nn::MusiqNet::kPatch;

// The patches of one scale of the [-1, 1] image x (TF 'SAME' padding), appended to `out`.
void append_patches(const util::Chw<double>& x, uint32_t grid, uint32_t scale, nn::MusiqPatches& out) {
  const uint32_t count_h = (x.h + kPatch - 1) / kPatch, count_w = (x.w + kPatch - 1) / kPatch;
  const uint32_t top = (count_h * kPatch - x.h) / 2, left = (count_w * kPatch - x.w) / 2;
  const std::vector<int> row = torch_nearest_index(int(grid), int(count_h)), col = torch_nearest_index(int(grid), int(count_w));
  for (uint32_t py = 0; py < count_h; ++py)
    for (uint32_t px = 0; px < count_w; ++px) {
      out.position.push_back(uint32_t(row[py]) * grid + uint32_t(col[px]));
      out.scale.push_back(scale);
      for (uint32_t c = 0; c < 3; ++c)
        for (uint32_t y = 0; y < kPatch; ++y)
          for (uint32_t i = 0; i < kPatch; ++i) {
            const int64_t sy = int64_t{py} * kPatch + y - top, sx = int64_t{px} * kPatch + i - left;
            const bool inside = sy >= 0 && sy < int64_t{x.h} && sx >= 0 && sx < int64_t{x.w};
            out.pixels.push_back(inside ? float(x.at(c, uint32_t(sy), uint32_t(sx))) : 0.0f);
          }
    }
}

}  // namespace

nn::MusiqPatches musiq_patches(const io::ImageF& rgb, uint32_t grid) {
  require_rgb(rgb, "musiq", "the image");
  const auto w = uint32_t(rgb.width), h = uint32_t(rgb.height);
  util::Chw<double> x(3, h, w);
  for (uint32_t c = 0; c < 3; ++c)
    for (uint32_t y = 0; y < h; ++y)
      for (uint32_t i = 0; i < w; ++i) x.at(c, y, i) = (double(rgb.data[(size_t{y} * w + i) * 3 + c]) - 0.5) * 2.0;
  nn::MusiqPatches out;
  for (uint32_t s = 0; s < kMusiqLongerSides.size(); ++s) {
    const double ratio = double(kMusiqLongerSides[s]) / double(std::max(w, h));
    const auto rh = static_cast<uint32_t>(std::nearbyint(h * ratio)), rw = static_cast<uint32_t>(std::nearbyint(w * ratio));
    if (rh == 0 || rw == 0)
      throw std::invalid_argument("musiq: a " + std::to_string(w) + "x" + std::to_string(h) + " image has no side at the " +
                                  std::to_string(kMusiqLongerSides[s]) + " scale");
    append_patches(torch_bicubic_resize(x, rh, rw), grid, s, out);
  }
  append_patches(x, grid, uint32_t(kMusiqLongerSides.size()), out);
  return out;
}

Musiq::Musiq(engine::Context& ctx, const io::SafetensorsFile& weights) : net_(ctx, weights) {
  if (net_.shape().scales != kMusiqLongerSides.size() + 1)
    throw std::runtime_error(weights.path().string() + ": scale_emb holds " + std::to_string(net_.shape().scales) +
                             " scales; MUSIQ's input has " + std::to_string(kMusiqLongerSides.size() + 1));
}

double Musiq::operator()(const io::ImageF& rgb) const { return net_.score(musiq_patches(rgb, net_.shape().grid)); }

}  // namespace s4d::metrics
