// PyTorch's F.interpolate(size=...) on the host, as the learned metrics' preprocessing calls it
// (shared by CKDN's and MUSIQ's resizes; training/kernels/nn/torch_cubic.h has the cubic weights).
#pragma once
#include <cstdint>
#include <vector>

#include "s4d/util/chw.h"

namespace s4d::metrics {

// mode='nearest' along one axis: the source index min(floor(dst * float(in / out)), in - 1) of each
// output index, the scale in float as torch computes it.
std::vector<int> torch_nearest_index(int in, int out);

// mode='bicubic', align_corners=False, antialias=False, to out_h x out_w: source coordinate
// float(in / out) (dst + 0.5) - 0.5 (not clamped), taps floor - 1 .. floor + 2 clamped to the border,
// Keys' cubic with A = -0.75; separable in double. Throws std::invalid_argument for an empty size.
util::Chw<double> torch_bicubic_resize(const util::Chw<double>& x, uint32_t out_h, uint32_t out_w);

}  // namespace s4d::metrics
