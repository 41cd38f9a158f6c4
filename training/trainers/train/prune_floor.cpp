#include "s4d/train/prune_floor.h"

#include <algorithm>
#include <cmath>

#include "s4d/io/moving_content.h"
#include "s4d/train/evaluate.h"

namespace s4d::train {

nlohmann::json PruneFloor::json() const {
  return {{"count", count}, {"content_pixels_per_view", content_pixels}, {"views", views},
          {"pixels_per_gaussian", kPixelsPerGaussian}};
}

PruneFloor measure_prune_floor(data::FrameCache& frames, const std::vector<const data::View*>& views,
                               const std::array<float, 3>& background, uint32_t budget) {
  PruneFloor f;
  double pixels = 0;
  for (const data::View* v : spread_views(views, kFloorViews)) {
    const io::ImageF& image = frames.get(*v);
    const size_t c = size_t(image.channels), n = size_t(image.width) * size_t(image.height);
    for (size_t p = 0; p < n; ++p)
      for (size_t k = 0; k < std::min<size_t>(c, 3); ++k)
        if (std::abs(image.data[p * c + k] - background[k]) > io::kMovingThreshold) {
          pixels += 1;
          break;
        }
    ++f.views;
  }
  f.content_pixels = f.views > 0 ? pixels / f.views : 0;
  f.count = static_cast<uint32_t>(std::min<double>(f.content_pixels / kPixelsPerGaussian, budget / 4));
  return f;
}

float floor_opacity(std::vector<float> opacities, float min_opacity, uint32_t floor) {
  const size_t keep = static_cast<size_t>(std::count_if(opacities.begin(), opacities.end(), [&](float o) { return o >= min_opacity; }));
  if (keep >= floor || floor == 0 || opacities.empty()) return min_opacity;
  const size_t k = std::min<size_t>(floor, opacities.size()) - 1;
  std::nth_element(opacities.begin(), opacities.begin() + static_cast<std::ptrdiff_t>(k), opacities.end(), std::greater<float>());
  return opacities[k];
}

}  // namespace s4d::train
