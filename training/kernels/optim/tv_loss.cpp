#include "s4d/optim/tv_loss.h"

#include <stdexcept>
#include <utility>
#include <vector>

#include "s4d/primitives/shader_pipeline.h"
#include "s4d_loss.h"

namespace s4d::optim {

using primitives::ceil_div;

TvLoss::TvLoss(engine::Context& ctx, std::string name) : ctx_(&ctx), name_(std::move(name)) {}

void TvLoss::record(engine::Recorder& rec, const engine::Buffer& image, uint32_t width, uint32_t height,
                    uint32_t channels, float weight, const engine::Buffer& grad) {
  const uint64_t n64 = uint64_t{width} * height * channels;
  if (width < 2 || height < 2 || channels == 0 || n64 > UINT32_MAX)
    throw std::invalid_argument(name_ + ": image size out of range (at least 2x2 with one channel)");
  const uint32_t n = static_cast<uint32_t>(n64);
  for (const engine::Buffer* b : {&image, &grad})
    if (b->size() < size_t{n} * 4)
      throw std::invalid_argument(name_ + ": buffer '" + b->name() + "' holds fewer than " + std::to_string(n) + " floats");
  const uint32_t groups = ceil_div(n, S4D_LOSS_WG);
  if (groups > groups_capacity_) {
    partials_ = engine::Buffer(*ctx_, name_ + " partial sums", size_t{groups} * 4);
    groups_capacity_ = groups;
  }
  const double pairs = double(channels) * (double(width - 1) * height + double(width) * (height - 1));
  const gpu::TvParams p{.width = width, .height = height, .channels = channels, .n = n, .weight = weight,
                        .inv_pairs = static_cast<float>(1.0 / pairs), ._pad0 = 0, ._pad1 = 0};
  rec.dispatch(primitives::shader_pipeline(*ctx_, shaders::Id::tv_grad),
               {S4D_BIND(TV_IMAGE, image), S4D_BIND(TV_GRAD, grad), S4D_BIND(TV_PARTIALS, partials_)}, p, groups);
  last_groups_ = groups;
  last_scale_ = weight / pairs;
}

double TvLoss::value() const {
  if (last_groups_ == 0) throw std::logic_error(name_ + ": value() before any record()");
  const std::vector<float> partials = ctx_->download<float>(partials_, last_groups_);
  double sum = 0;
  for (float v : partials) sum += v;
  return sum * last_scale_;
}

}  // namespace s4d::optim
