// The photometric training loss on the GPU (ALGORITHMS.md 2.3): (1 - lambda) L1 + lambda (1 - SSIM)
// and its gradient with respect to the rendered image, in four kernels recorded into the caller's
// command buffer. The value comes back from per-workgroup partial sums only when asked for.
#pragma once
#include <cstdint>
#include <string>

#include "s4d/engine/buffer.h"
#include "s4d/engine/context.h"
#include "s4d/engine/recorder.h"

namespace s4d::optim {

struct LossValue {
  double loss = 0, l1 = 0, ssim = 0;
};

class ImageLoss {
 public:
  explicit ImageLoss(engine::Context& ctx, std::string name = "image loss");

  // Records value and gradient: grad = dL/d image. image, target and grad are float [H*W*C]
  // interleaved. The caller puts a barrier between writing `image` and this call; the gradient is
  // complete after the next barrier.
  void record(engine::Recorder& rec, const engine::Buffer& image, const engine::Buffer& target, uint32_t width,
              uint32_t height, uint32_t channels, float ssim_weight, const engine::Buffer& grad);

  // The value of the last recorded loss; call after its submission has completed.
  LossValue value() const;

 private:
  void reserve(uint32_t n);

  engine::Context* ctx_;
  std::string name_;
  uint32_t capacity_ = 0, last_n_ = 0;
  float last_weight_ = 0;
  engine::Buffer stats_h_, dmaps_, dmaps_h_, partials_;
};

}  // namespace s4d::optim
