#include "s4d/optim/adam.h"

#include <cmath>
#include <span>
#include <stdexcept>
#include <utility>

#include "s4d/primitives/shader_pipeline.h"

namespace s4d::optim {

Adam::Adam(engine::Context& ctx, uint32_t num_groups, std::string name)
    : ctx_(&ctx), name_(std::move(name)), groups_(num_groups), buffer_(ctx, name_ + " groups", num_groups * sizeof(gpu::AdamGroup)) {
  if (num_groups == 0) throw std::invalid_argument(name_ + ": needs at least one parameter group");
}

void Adam::set_group(uint32_t g, const AdamSettings& s, uint32_t step) {
  if (g >= groups_.size()) throw std::out_of_range(name_ + ": group " + std::to_string(g) + " does not exist");
  if (step == 0) throw std::invalid_argument(name_ + ": steps count from 1");
  const double t = step;
  groups_[g] = {.lr = static_cast<float>(s.lr),
                .beta1 = static_cast<float>(s.beta1),
                .beta2 = static_cast<float>(s.beta2),
                .eps = static_cast<float>(s.eps),
                .inv_bias1 = static_cast<float>(1 / (1 - std::pow(s.beta1, t))),
                .inv_sqrt_bias2 = static_cast<float>(1 / std::sqrt(1 - std::pow(s.beta2, t))),
                .step = step,
                ._pad0 = 0};
}

void Adam::upload() { ctx_->upload(buffer_, std::span<const gpu::AdamGroup>(groups_)); }

void Adam::record(engine::Recorder& rec, uint32_t group, const engine::Buffer& params, const engine::Buffer& grads,
                  const engine::Buffer& m, const engine::Buffer& v, uint32_t n) const {
  record_rows(rec, group, group, 1, 1, params, grads, m, v, n);
}

void Adam::record_rows(engine::Recorder& rec, uint32_t group, uint32_t tail_group, uint32_t row, uint32_t head,
                       const engine::Buffer& params, const engine::Buffer& grads, const engine::Buffer& m,
                       const engine::Buffer& v, uint32_t n) const {
  for (uint32_t g : {group, tail_group}) {
    if (g >= groups_.size()) throw std::out_of_range(name_ + ": group " + std::to_string(g) + " does not exist");
    if (groups_[g].step == 0) throw std::logic_error(name_ + ": group " + std::to_string(g) + " was never set");
  }
  if (row == 0 || head == 0 || head > row)
    throw std::invalid_argument(name_ + ": rows of " + std::to_string(row) + " with a head of " + std::to_string(head) +
                                " (need 1 <= head <= row)");
  for (const engine::Buffer* b : {&params, &grads, &m, &v})
    if (b->size() < size_t{n} * 4)
      throw std::invalid_argument(name_ + ": buffer '" + b->name() + "' holds fewer than " + std::to_string(n) + " floats");
  const gpu::AdamParams p{
      .n = n, .group = group, .tail_group = tail_group, .row = row, .head = head, ._pad0 = 0, ._pad1 = 0, ._pad2 = 0};
  rec.dispatch(primitives::shader_pipeline(*ctx_, shaders::Id::adam_step),
               {S4D_BIND(ADAM_GROUPS, buffer_), S4D_BIND(ADAM_PARAMS, params), S4D_BIND(ADAM_GRADS, grads),
                S4D_BIND(ADAM_M, m), S4D_BIND(ADAM_V, v)},
               p, primitives::ceil_div(n, S4D_ADAM_WG));
}

}  // namespace s4d::optim
