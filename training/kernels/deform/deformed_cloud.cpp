// Deform-to-time (deformed_cloud.h).
#include "s4d/deform/deformed_cloud.h"

#include <stdexcept>
#include <string>

namespace s4d::deform {

namespace {

using splat::Attr;
using splat::kCloudAttrs;

bool on(uint32_t heads, uint32_t h) { return (heads & (1u << h)) != 0; }

}  // namespace

CanonicalGaussians canonical_of(const splat::GaussianParams& canonical, uint32_t still_count) {
  return {canonical.buffers, canonical.count, still_count, canonical.sh_coeffs, canonical.sh_storage};
}

DeformedCloud::DeformedCloud(engine::Context& ctx, uint32_t heads, uint32_t count, uint32_t sh_coeffs)
    : heads_(heads), count_(count), sh_coeffs_(sh_coeffs) {
  for (uint32_t h = 0; h < S4D_DEFORM_HEADS; ++h)
    if (on(heads, h))
      buffers_[kCloudAttrs[h]] = engine::Buffer(ctx, std::string("deformed ") + splat::attr_name(kCloudAttrs[h]),
                                                size_t{count} * splat::attr_floats(kCloudAttrs[h], sh_coeffs) * 4);
}

splat::GaussianBuffers<engine::Buffer> DeformedCloud::outputs() {
  splat::GaussianBuffers<engine::Buffer> out;
  for (uint32_t h = 0; h < S4D_DEFORM_HEADS; ++h)
    if (on(heads_, h)) out[kCloudAttrs[h]] = &buffers_[kCloudAttrs[h]];
  return out;
}

splat::GaussianParams DeformedCloud::record(engine::Recorder& rec, const DeformationField& field,
                                            const splat::GaussianParams& canonical, uint32_t still_count, float time) {
  if (field.config().heads != heads_)
    throw std::invalid_argument("deformed cloud: the field's heads " + std::to_string(field.config().heads) +
                                " differ from the cloud's " + std::to_string(heads_));
  if (canonical.count != count_ || canonical.sh_coeffs != sh_coeffs_)
    throw std::invalid_argument("deformed cloud: sized for " + std::to_string(count_) + " Gaussians with " +
                                std::to_string(sh_coeffs_) + " SH coefficients, given " + std::to_string(canonical.count) +
                                " with " + std::to_string(canonical.sh_coeffs));
  field.record_forward(rec, canonical_of(canonical, still_count), time, outputs());
  splat::GaussianParams p = canonical;
  for (uint32_t h = 0; h < S4D_DEFORM_HEADS; ++h)
    if (on(heads_, h)) p[kCloudAttrs[h]] = &buffers_[kCloudAttrs[h]];
  if ((heads_ & S4D_DEFORM_HEAD_SH) != 0) p.sh_storage = splat::Storage::f32;  // the deformed SH are float, whatever the canonical's
  return p;
}

}  // namespace s4d::deform
