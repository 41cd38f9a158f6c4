// What in a training state makes its loss non-finite: the arrays holding non-finite values or values
// no trained model holds (beyond range_limit), the Gaussians they sit in, in one line. The stage runner
// asks for it when a loss or a checkpoint is not finite, and every checkpoint is checked with it: a
// few Gaussians are then removed and training goes on; anything else is named and rolled back or stopped.
#pragma once
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace s4d::model {
struct Checkpoint;
}

namespace s4d::train {

struct Divergence {
  std::string where;                // "'sh' of 20 Gaussians (up to 1e+30, first at Gaussian 17)"; "" when none
  std::vector<uint32_t> gaussians;  // the Gaussians (rows) holding them, ascending
  bool local = false;               // only per-Gaussian arrays, at most local_limit(Gaussians) of them
  bool found() const { return !where.empty(); }
};

// Beyond these a value is out of range. Parameters and first moments: squared and summed by the
// forward and the loss (SSIM squares colours), 1e15 stays far below float's 3.4e38; the largest a
// trained model holds is orders of magnitude below (SH near 1, positions in scene units). Second
// moments are squared gradients. A log scale above 40 is a Gaussian e^40 scene units wide, whose
// covariance (its square) overflows.
inline constexpr float kRangeLimit = 1e15f, kSecondMomentLimit = 1e30f, kLogScaleLimit = 40.f;
float range_limit(const std::string& array);
// The most Gaussians a repair removes: 16, or 1 % of the cloud when that is more.
uint32_t local_limit(uint32_t gaussians);

// The part of a non-per-Gaussian array (extra) holding entry `index`, for the message: "level 0 plane xt".
using PartName = std::function<std::string(const std::string& array, uint64_t index)>;

// Scans every array of `state` (the Gaussians', their Adam moments and statistics, and the extra
// arrays but masks). `part` names parts of the extra arrays; may be empty. With `extra_rows` > 0 the
// extra arrays hold that many Gaussians' rows each (stage 4's per-Gaussian style), so they are
// scanned, named and repaired per Gaussian like the cloud's.
Divergence find_divergence(const model::Checkpoint& state, const PartName& part = {}, uint32_t extra_rows = 0);

}  // namespace s4d::train
