// Warp loss (temporal consistency, METRICS.md 6): for consecutive frames t, t+1 with forward flow
// w_f (t -> t+1) and backward flow w_b (t+1 -> t), frame t+1 is warped back to t,
// W(x) = I_{t+1}(x + w_f(x)), with FlowNet2's Resample2d (bilinear, neighbour indices clamped to the
// image, weights from the unclamped fraction), and compared with I_t over the pixels that are not
// occluded (Lai et al. 2018's mask, below). Lower is better.
//
// Occlusion (Lai's detect_occlusion, net effect; the Sundaram 2010 / Ruder 2016 thresholds): with
// w_b~(x) = w_b sampled (Resample2d) at x + w_f(x), x is occluded when
//   |w_f + w_b~|^2 > 0.01 (|w_f|^2 + |w_b~|^2) + 0.5            (forward-backward check), or
//   |grad u|^2 + |grad v|^2 > 0.01 |w_f|^2 + 0.002              (motion boundary; forward differences
//   p(x) - p(x+1) along x and y of w_f, zero in the last column / row).
//
// Per pair: sum over the non-occluded pixels and 3 channels of |difference| (Style4D's L1, default) or
// its square (Lai's), divided by 3 x (non-occluded pixels). A pair with every pixel occluded has
// nothing to compare: its error is NaN (Lai's script divides by all pixels instead and scores it a
// perfect 0), and the metric, the mean over pairs, leaves it out (bench/report/frames_eval.cpp; no
// pair left: unavailable).
#pragma once
#include <cstdint>
#include <vector>

#include "s4d/io/image_io.h"
#include "s4d/metrics/flow.h"

namespace s4d::metrics {

enum class WarpNorm { abs, squared };

// 1 where occluded, [H, W]. Throws std::invalid_argument when the flows differ in size.
std::vector<uint8_t> occlusion_mask(const Flow& forward, const Flow& backward);

// `image` (any channel count) sampled at x + flow(x) with Resample2d's clamped bilinear rule.
io::ImageF warp_back(const io::ImageF& image, const Flow& flow);

struct PairWarpError {
  double error = 0;           // NaN when no pixel is valid (valid_fraction == 0)
  double valid_fraction = 0;  // non-occluded pixels / all pixels
  bool scored() const { return valid_fraction > 0; }  // false: leave the pair out of any mean
};

// Throws std::invalid_argument when the frames are not RGB or the frames and flows differ in size.
PairWarpError warp_error(const io::ImageF& frame_t, const io::ImageF& frame_t1, const Flow& forward,
                         const Flow& backward, WarpNorm norm = WarpNorm::abs);

}  // namespace s4d::metrics
