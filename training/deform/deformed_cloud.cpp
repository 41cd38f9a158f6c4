// Deform-to-time (deformed_cloud.h).
#include "s4d/deform/deformed_cloud.h"

#include <stdexcept>
#include <string>

namespace s4d::deform {

namespace {

const char* const kHeadNames[S4D_DEFORM_HEADS] = {"means", "log_scales", "quats", "opacity_logits", "sh"};

bool on(uint32_t heads, uint32_t h) { return (heads & (1u << h)) != 0; }

// The rasterizer's parameter of head h.
const engine::Buffer*& slot(splat::GaussianParams& p, uint32_t h) {
  const engine::Buffer** slots[S4D_DEFORM_HEADS] = {&p.means, &p.log_scales, &p.quats, &p.opacity_logits, &p.sh};
  return *slots[h];
}

}  // namespace

CanonicalGaussians canonical_of(const splat::GaussianParams& canonical, uint32_t still_count) {
  return {.means = canonical.means,
          .log_scales = canonical.log_scales,
          .quats = canonical.quats,
          .opacity_logits = canonical.opacity_logits,
          .sh = canonical.sh,
          .count = canonical.count,
          .still_count = still_count,
          .sh_coeffs = canonical.sh_coeffs};
}

DeformedCloud::DeformedCloud(engine::Context& ctx, uint32_t heads, uint32_t count, uint32_t sh_coeffs)
    : heads_(heads), count_(count), sh_coeffs_(sh_coeffs) {
  const size_t widths[S4D_DEFORM_HEADS] = {3, 3, 4, 1, size_t{3} * sh_coeffs};
  for (uint32_t h = 0; h < S4D_DEFORM_HEADS; ++h)
    if (on(heads, h)) buffers_[h] = engine::Buffer(ctx, std::string("deformed ") + kHeadNames[h], count * widths[h] * 4);
}

DeformedGaussians DeformedCloud::outputs() {
  auto out = [&](uint32_t h) { return on(heads_, h) ? &buffers_[h] : nullptr; };
  return {out(0), out(1), out(2), out(3), out(4)};
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
    if (on(heads_, h)) slot(p, h) = &buffers_[h];
  return p;
}

}  // namespace s4d::deform
