// The fewest Gaussians pruning may leave: one per kPixelsPerGaussian pixels of visible content,
// where visible content is what differs from the background in the training frames. A monocular
// capture shows a moving object in another place in every frame, so a static fit fades it and an
// opacity prune can then empty the model; the floor keeps the most opaque Gaussians instead, for
// growth and the deformation field to work with.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include <nlohmann/json.hpp>

#include "s4d/data/frame_cache.h"

namespace s4d::train {

// A 4x4 block of content pixels per Gaussian: 3DGS models settle at one Gaussian per few pixels
// of their training resolution (the built-in scene at 160x120: 15,000 Gaussians for 19,200 pixels),
// so a quarter of a pixel-dense model.
inline constexpr double kPixelsPerGaussian = 16;
inline constexpr size_t kFloorViews = 16;  // training views measured, spread over the capture

struct PruneFloor {
  uint32_t count = 0;
  double content_pixels = 0;  // mean per measured view
  uint32_t views = 0;
  nlohmann::json json() const;
};

// Content pixels differ from `background` by more than io::kMovingThreshold in some channel. The
// floor is at most budget / 4, so growth always has room.
PruneFloor measure_prune_floor(data::FrameCache& frames, const std::vector<const data::View*>& views,
                               const std::array<float, 3>& background, uint32_t budget);

// The opacity threshold that keeps at least `floor` of `opacities` (sigmoid values): `min_opacity`
// itself when enough are at or above it, else the floor-th largest opacity.
float floor_opacity(std::vector<float> opacities, float min_opacity, uint32_t floor);

}  // namespace s4d::train
