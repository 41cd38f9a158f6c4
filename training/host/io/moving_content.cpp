#include "s4d/io/moving_content.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "s4d/io/psnr.h"

namespace s4d::io {

namespace {
void check_same(const ImageF& a, const ImageF& b) {
  if (a.width != b.width || a.height != b.height || a.channels != b.channels || a.data.size() != b.data.size() ||
      a.data.size() != size_t(a.width) * size_t(a.height) * size_t(a.channels))
    throw std::invalid_argument("moving content: frames of different shapes (" + std::to_string(a.width) + "x" +
                                std::to_string(a.height) + " and " + std::to_string(b.width) + "x" + std::to_string(b.height) + ")");
}
}  // namespace

ImageF temporal_median(const std::vector<const ImageF*>& frames) {
  if (frames.empty()) throw std::invalid_argument("moving content: no frames");
  for (const ImageF* f : frames) check_same(*frames[0], *f);
  ImageF out{frames[0]->width, frames[0]->height, frames[0]->channels, std::vector<float>(frames[0]->data.size())};
  std::vector<float> column(frames.size());
  for (size_t i = 0; i < out.data.size(); ++i) {
    for (size_t k = 0; k < frames.size(); ++k) column[k] = frames[k]->data[i];
    const size_t mid = column.size() / 2;
    std::nth_element(column.begin(), column.begin() + static_cast<std::ptrdiff_t>(mid), column.end());
    float m = column[mid];
    if (column.size() % 2 == 0) m = 0.5f * (m + *std::max_element(column.begin(), column.begin() + static_cast<std::ptrdiff_t>(mid)));
    out.data[i] = m;
  }
  return out;
}

std::vector<uint8_t> moving_mask(const ImageF& frame, const ImageF& still) {
  check_same(frame, still);
  const size_t pixels = size_t(frame.width) * size_t(frame.height), c = size_t(frame.channels);
  std::vector<uint8_t> mask(pixels, 0);
  for (size_t p = 0; p < pixels; ++p)
    for (size_t k = 0; k < c; ++k)
      if (std::abs(frame.data[p * c + k] - still.data[p * c + k]) > kMovingThreshold) mask[p] = 1;
  return mask;
}

void MovingPsnr::add(const std::vector<const ImageF*>& renders, const std::vector<const ImageF*>& truths) {
  if (renders.size() != truths.size()) throw std::invalid_argument("moving content: renders and ground truths differ in number");
  if (truths.size() < kMovingMinFrames) return;
  const ImageF still = temporal_median(truths);
  for (size_t f = 0; f < truths.size(); ++f) {
    check_same(*renders[f], *truths[f]);
    const std::vector<uint8_t> mask = moving_mask(*truths[f], still);
    const size_t c = size_t(truths[f]->channels);
    for (size_t p = 0; p < mask.size(); ++p) {
      if (!mask[p]) continue;
      ++pixels_;
      for (size_t k = 0; k < c; ++k) {
        const double d = double(renders[f]->data[p * c + k]) - double(truths[f]->data[p * c + k]);
        se_ += d * d;
        ++values_;
      }
    }
    all_pixels_ += mask.size();
  }
  ++cameras_;
}

MovingScore MovingPsnr::score() const {
  MovingScore s;
  if (cameras_ == 0) {
    s.why = "no camera is seen at " + std::to_string(kMovingMinFrames) + " or more times";
    return s;
  }
  s.moving_share = double(pixels_) / double(all_pixels_);
  if (values_ == 0) {
    s.why = "nothing moves in the test cameras' frames";
    return s;
  }
  s.psnr = -10.0 * std::log10(std::max(se_ / double(values_), kPsnrMinMse));
  return s;
}

}  // namespace s4d::io
