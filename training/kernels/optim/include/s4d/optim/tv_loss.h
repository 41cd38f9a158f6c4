// Squared total variation of a rendered image on the GPU (shaders/loss/tv_grad.comp): the
// smoothness term of stage 4's loss (L1 + TV). Its gradient is added to an existing image
// gradient, so it records after the photometric loss.
#pragma once
#include <cstdint>
#include <string>

#include "s4d/engine/buffer.h"
#include "s4d/engine/context.h"
#include "s4d/engine/recorder.h"

namespace s4d::optim {

class TvLoss {
 public:
  explicit TvLoss(engine::Context& ctx, std::string name = "tv loss");

  // Records grad += d/dimage [weight * mean over neighbour pairs of (x_a - x_b)^2]. image and grad
  // are float [H*W*C] interleaved; the caller puts a barrier between writing either and this call.
  // Throws std::invalid_argument for an image smaller than 2x2 or a buffer that is too small.
  void record(engine::Recorder& rec, const engine::Buffer& image, uint32_t width, uint32_t height, uint32_t channels,
              float weight, const engine::Buffer& grad);

  // The last recorded term's value (weight included); call after its submission has completed.
  double value() const;

 private:
  engine::Context* ctx_;
  std::string name_;
  uint32_t groups_capacity_ = 0, last_groups_ = 0;
  double last_scale_ = 0;
  engine::Buffer partials_;
};

}  // namespace s4d::optim
