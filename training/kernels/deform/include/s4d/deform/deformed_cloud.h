// Deform-to-time, once for every caller: the canonical Gaussians moved by the deformation field to a
// time, as the rasterizer's parameters. The heads that are on replace the canonical means, scales,
// rotations, opacities or SH with their deformed values; the others stay canonical. The trainer
// (stage 2's steps, its evaluation, the motion split) and scene::DeformedScene (renders, the viewer,
// export, stage 4) both call it, so what a run renders is what its trainer evaluated.
#pragma once
#include <cstdint>

#include "s4d/deform/deformation_field.h"
#include "s4d/engine/buffer.h"
#include "s4d/engine/context.h"
#include "s4d/engine/recorder.h"
#include "s4d/splat/rasterizer.h"

namespace s4d::deform {

// The field's view of canonical Gaussians held as the rasterizer's parameters; the last
// `still_count` skip the field.
CanonicalGaussians canonical_of(const splat::GaussianParams& canonical, uint32_t still_count);

class DeformedCloud {
 public:
  DeformedCloud() = default;  // holds nothing; record() refuses it
  // Device buffers for the deformed attributes of `count` Gaussians with `sh_coeffs` SH coefficients
  // per channel, allocated only for the heads on in `heads` (S4D_DEFORM_HEAD_* bits).
  DeformedCloud(engine::Context& ctx, uint32_t heads, uint32_t count, uint32_t sh_coeffs);

  // The deformed buffers, null for the heads that are off.
  splat::GaussianBuffers<engine::Buffer> outputs();
  // Bytes of device memory of the deformed attribute a (0 when its head is off).
  size_t bytes(splat::Attr a) const { return buffers_[a].size(); }

  // Records `field`'s forward pass from `canonical` (count and sh_coeffs as this cloud's; the last
  // `still_count` Gaussians are copied, not deformed) at raw time `time` into this cloud's buffers,
  // and returns `canonical` with the deformed attributes in place of the heads that are on. Only
  // records: the result is valid once the recording has run. Throws std::invalid_argument when the
  // field's heads or the canonical Gaussians' count or sh_coeffs differ from this cloud's.
  splat::GaussianParams record(engine::Recorder& rec, const DeformationField& field,
                               const splat::GaussianParams& canonical, uint32_t still_count, float time);

 private:
  uint32_t heads_ = 0, count_ = 0, sh_coeffs_ = 0;
  splat::PerAttr<engine::Buffer, splat::kCloudAttrCount> buffers_;  // the heads' attributes
};

}  // namespace s4d::deform
