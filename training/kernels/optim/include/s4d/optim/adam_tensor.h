// One trained tensor as Adam sees it: its name, its parameter and gradient (buffers of `floats`
// floats owned by what they belong to: a cloud, a field, a network, a style), and Adam's two moments,
// owned here and zero at first. Every trainer's tensors are this type, and their moments go to and
// from checkpoints by one rule, under the names of one of the two formats:
//   trainer   NAME.adam_m, NAME.adam_v      (the run's and a style's .s4dckpt)
//   pytorch   NAME.exp_avg, NAME.exp_avg_sq (train-stylizer's safetensors, as torch.optim.Adam's state)
#pragma once
#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "s4d/engine/buffer.h"
#include "s4d/engine/context.h"
#include "s4d/engine/recorder.h"
#include "s4d/optim/adam.h"

namespace s4d::optim {

enum class MomentNames { trainer, pytorch };

class AdamTensor {
 public:
  AdamTensor() = default;
  // Moments of `floats` zeros; `param` and `grad` must outlive this (`grad` may be null when every
  // update names its gradient).
  AdamTensor(engine::Context& ctx, std::string name, const engine::Buffer& param, const engine::Buffer* grad, size_t floats);
  // With the moments given (`floats` floats each: a resumed or densified tensor's).
  AdamTensor(engine::Context& ctx, std::string name, const engine::Buffer& param, const engine::Buffer* grad, size_t floats,
             engine::Buffer&& m, engine::Buffer&& v);

  const std::string& name() const { return name_; }
  size_t floats() const { return floats_; }
  engine::Buffer& moment1() { return m_; }
  engine::Buffer& moment2() { return v_; }
  const engine::Buffer& moment1() const { return m_; }
  const engine::Buffer& moment2() const { return v_; }

  // One Adam update of the whole tensor in `group` (Adam::record).
  void record(const Adam& adam, engine::Recorder& rec, uint32_t group) const;
  // The same from `grad` instead of the gradient given at construction (a trainer whose gradient
  // buffers are new every step).
  void record(const Adam& adam, engine::Recorder& rec, uint32_t group, const engine::Buffer& grad) const;
  // The same for rows of `row` floats whose first `head` belong to `group`, the rest to `tail_group`.
  void record_rows(const Adam& adam, engine::Recorder& rec, uint32_t group, uint32_t tail_group, uint32_t row,
                   uint32_t head) const;

  // The checkpoint names of the two moments.
  std::pair<std::string, std::string> moment_names(MomentNames names) const;
  // The moments as named arrays (first m, then v), downloaded.
  std::vector<std::pair<std::string, std::vector<float>>> download_moments(MomentNames names) const;
  // Uploads the moments that `find` returns by name; `find` throws for a missing name. Throws
  // std::runtime_error "WHERE: array 'NAME' holds N floats, not M" on a size mismatch.
  void upload_moments(MomentNames names, const std::function<const std::vector<float>&(const std::string&)>& find,
                      const std::string& where);
  // Zeroes the moments of `rows` (ascending or not) of `width` floats each: what a reset Gaussian restarts from.
  void zero_rows(const std::vector<uint32_t>& rows, size_t width);

 private:
  engine::Context* ctx_ = nullptr;
  std::string name_;
  const engine::Buffer* param_ = nullptr;
  const engine::Buffer* grad_ = nullptr;
  size_t floats_ = 0;
  engine::Buffer m_, v_;
};

}  // namespace s4d::optim
