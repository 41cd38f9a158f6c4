// Temporal coherence of a frame sequence: how much each frame differs from the previous frame
// moved along the content's motion. The motion is DIS optical flow computed on the content frames
// (backward, frame t to t - 1), and pixels whose forward-backward flows disagree (occluded or
// disoccluded) are left out, so the same measure applies to the content and to any restyling of it.
#pragma once
#include <vector>

#include "s4d/io/image_io.h"

namespace s4d::frame_stylizers {

// Mean over t >= 1, non-occluded pixels and the 3 channels of |frames[t] - warp(frames[t - 1])|, in
// the frames' units; NaN when no pixel of any pair is consistent (nothing was measured, which is not
// a perfect 0). Throws std::invalid_argument for fewer than 2 frames or mismatched sizes.
double warp_error(const std::vector<io::ImageF>& content, const std::vector<io::ImageF>& frames);

}  // namespace s4d::frame_stylizers
