#include "s4d/optim/image_loss.h"

#include <stdexcept>
#include <utility>
#include <vector>

#include "s4d/primitives/shader_pipeline.h"
#include "s4d_loss.h"

namespace s4d::optim {

using primitives::ceil_div;
using primitives::shader_pipeline;

ImageLoss::ImageLoss(engine::Context& ctx, std::string name) : ctx_(&ctx), name_(std::move(name)) { reserve(1); }

void ImageLoss::reserve(uint32_t n) {
  if (n <= capacity_) return;
  const size_t c = n;
  stats_h_ = engine::Buffer(*ctx_, name_ + " ssim stats", c * S4D_SSIM_STATS * 4);
  dmaps_ = engine::Buffer(*ctx_, name_ + " ssim dmaps", c * S4D_SSIM_DMAPS * 4);
  dmaps_h_ = engine::Buffer(*ctx_, name_ + " ssim dmaps filtered", c * S4D_SSIM_DMAPS * 4);
  partials_ = engine::Buffer(*ctx_, name_ + " partial sums", size_t{ceil_div(n, S4D_LOSS_WG)} * 8);
  capacity_ = n;
}

void ImageLoss::record(engine::Recorder& rec, const engine::Buffer& image, const engine::Buffer& target,
                       uint32_t width, uint32_t height, uint32_t channels, float ssim_weight,
                       const engine::Buffer& grad) {
  const uint64_t n64 = uint64_t{width} * height * channels;
  if (n64 == 0 || n64 > UINT32_MAX) throw std::invalid_argument(name_ + ": image size out of range");
  const uint32_t n = static_cast<uint32_t>(n64);
  for (const engine::Buffer* b : {&image, &target, &grad})
    if (b->size() < size_t{n} * 4)
      throw std::invalid_argument(name_ + ": buffer '" + b->name() + "' holds fewer than " + std::to_string(n) + " floats");
  reserve(n);
  const uint32_t groups = ceil_div(n, S4D_LOSS_WG);
  gpu::LossParams p{.width = width, .height = height, .channels = channels, .n = n, .ssim_weight = ssim_weight,
                    .inv_count = 1.0f / static_cast<float>(n), .mode = 0, ._pad0 = 0};
  const engine::Pipeline& hpass = shader_pipeline(*ctx_, shaders::Id::ssim_hpass);
  rec.dispatch(hpass, {S4D_BIND(SSIM_H_IN_A, image), S4D_BIND(SSIM_H_IN_B, target), S4D_BIND(SSIM_H_OUT, stats_h_)}, p,
               groups);
  rec.barrier();
  rec.dispatch(shader_pipeline(*ctx_, shaders::Id::ssim_vpass),
               {S4D_BIND(SSIM_V_IMAGE, image), S4D_BIND(SSIM_V_TARGET, target), S4D_BIND(SSIM_V_STATS_H, stats_h_),
                S4D_BIND(SSIM_V_DMAPS, dmaps_), S4D_BIND(SSIM_V_PARTIALS, partials_)},
               p, groups);
  rec.barrier();
  p.mode = 1;
  rec.dispatch(hpass, {S4D_BIND(SSIM_H_IN_A, dmaps_), S4D_BIND(SSIM_H_IN_B, dmaps_), S4D_BIND(SSIM_H_OUT, dmaps_h_)}, p,
               groups);
  rec.barrier();
  rec.dispatch(shader_pipeline(*ctx_, shaders::Id::loss_grad),
               {S4D_BIND(LOSS_GRAD_IMAGE, image), S4D_BIND(LOSS_GRAD_TARGET, target),
                S4D_BIND(LOSS_GRAD_DMAPS_H, dmaps_h_), S4D_BIND(LOSS_GRAD_OUT, grad)},
               p, groups);
  last_n_ = n;
  last_weight_ = ssim_weight;
}

LossValue ImageLoss::value() const {
  if (last_n_ == 0) throw std::logic_error(name_ + ": value() before any record()");
  const uint32_t groups = ceil_div(last_n_, S4D_LOSS_WG);
  const std::vector<float> partials = ctx_->download<float>(partials_, 2 * size_t{groups});
  LossValue v;
  for (uint32_t g = 0; g < groups; ++g) v.ssim += partials[2 * g], v.l1 += partials[2 * g + 1];
  v.ssim /= last_n_, v.l1 /= last_n_;
  v.loss = (1 - last_weight_) * v.l1 + last_weight_ * (1 - v.ssim);
  return v;
}

}  // namespace s4d::optim
