// Adam on the GPU (PyTorch semantics, bias-corrected) for any number of parameter tensors, each in
// a parameter group whose hyperparameters live in a small device buffer rewritten every step.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "s4d/engine/buffer.h"
#include "s4d/engine/context.h"
#include "s4d/engine/recorder.h"
#include "s4d_optim.h"

namespace s4d::optim {

struct AdamSettings {
  double lr = 1e-3, beta1 = 0.9, beta2 = 0.999, eps = 1e-15;  // eps as in 3DGS
};

class Adam {
 public:
  Adam(engine::Context& ctx, uint32_t num_groups, std::string name = "adam");

  // Sets group g's hyperparameters for step t (1-based; bias corrections follow from it).
  void set_group(uint32_t g, const AdamSettings& s, uint32_t step);
  // Uploads the groups; call once per step before submitting the step's commands.
  void upload();
  // Records one update of `params` (n floats) from `grads` with moments `m`, `v` (zero-initialised).
  void record(engine::Recorder& rec, uint32_t group, const engine::Buffer& params, const engine::Buffer& grads,
              const engine::Buffer& m, const engine::Buffer& v, uint32_t n) const;
  // As record(), for a tensor of rows of `row` floats whose first `head` elements belong to
  // `group` and the rest to `tail_group` (SH rows: DC term and higher coefficients).
  void record_rows(engine::Recorder& rec, uint32_t group, uint32_t tail_group, uint32_t row, uint32_t head,
                   const engine::Buffer& params, const engine::Buffer& grads, const engine::Buffer& m,
                   const engine::Buffer& v, uint32_t n) const;

 private:
  engine::Context* ctx_;
  std::string name_;
  std::vector<gpu::AdamGroup> groups_;
  engine::Buffer buffer_;
};

}  // namespace s4d::optim
