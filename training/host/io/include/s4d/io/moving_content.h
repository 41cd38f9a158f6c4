// Moving-content PSNR: the PSNR over the pixels where a camera's ground truth differs from the
// scene's static part, which is what a 4D model must get right and what a frame PSNR drowns in
// background (a model with no moving object at all can score 21 dB on a white sky). The static
// part of a camera's frames is their per-pixel median over time; a pixel moves when any channel
// differs from it by more than kMovingThreshold in that frame. Used by the trainer's test
// (train.json "moving_psnr") and the bench.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "s4d/io/image_io.h"

namespace s4d::io {

// A tenth of the range: above 8-bit rounding, video compression and antialiasing noise (the
// built-in scene's mp4v frames differ from the render by 6/255 on average), below any object.
inline constexpr float kMovingThreshold = 0.1f;
// The median of fewer frames than this is not the static part (a thing still in two of three
// frames would be static).
inline constexpr size_t kMovingMinFrames = 3;

// The per-pixel median over `frames` (same shape, at least one).
ImageF temporal_median(const std::vector<const ImageF*>& frames);

// 1 where `frame` differs from `still` by more than kMovingThreshold in any channel, else 0; [H*W].
std::vector<uint8_t> moving_mask(const ImageF& frame, const ImageF& still);

struct MovingScore {
  std::optional<double> psnr;  // over every moving pixel of every frame; nullopt with `why`
  double moving_share = 0;     // moving pixels / all pixels
  std::string why;             // why there is no score
};

// Accumulates squared error over moving pixels, camera by camera: add() one camera's renders and
// ground truths in time order (same shapes); score() pools every camera added.
class MovingPsnr {
 public:
  void add(const std::vector<const ImageF*>& renders, const std::vector<const ImageF*>& truths);
  MovingScore score() const;

 private:
  double se_ = 0;
  size_t values_ = 0, pixels_ = 0, all_pixels_ = 0, cameras_ = 0;
};

}  // namespace s4d::io
