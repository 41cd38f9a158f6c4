#include "s4d/optim/adam_tensor.h"

#include <algorithm>
#include <span>
#include <stdexcept>

#include "s4d/engine/buffer_from.h"

namespace s4d::optim {

AdamTensor::AdamTensor(engine::Context& ctx, std::string name, const engine::Buffer& param, const engine::Buffer* grad,
                       size_t floats)
    : ctx_(&ctx), name_(std::move(name)), param_(&param), grad_(grad), floats_(floats),
      m_(engine::zeroed_buffer(ctx, name_ + " adam m", floats)), v_(engine::zeroed_buffer(ctx, name_ + " adam v", floats)) {}

AdamTensor::AdamTensor(engine::Context& ctx, std::string name, const engine::Buffer& param, const engine::Buffer* grad,
                       size_t floats, engine::Buffer&& m, engine::Buffer&& v)
    : ctx_(&ctx), name_(std::move(name)), param_(&param), grad_(grad), floats_(floats), m_(std::move(m)), v_(std::move(v)) {
  for (const engine::Buffer* b : {&m_, &v_})
    if (b->size() != std::max<size_t>(floats, 1) * 4 && b->size() != floats * 4)
      throw std::invalid_argument(name_ + ": moment buffer '" + b->name() + "' holds " + std::to_string(b->size()) +
                                  " bytes, expected " + std::to_string(floats * 4));
}

void AdamTensor::record(const Adam& adam, engine::Recorder& rec, uint32_t group) const {
  if (grad_ == nullptr) throw std::logic_error(name_ + ": an Adam update needs its gradient");
  record(adam, rec, group, *grad_);
}

void AdamTensor::record(const Adam& adam, engine::Recorder& rec, uint32_t group, const engine::Buffer& grad) const {
  adam.record(rec, group, *param_, grad, m_, v_, static_cast<uint32_t>(floats_));
}

void AdamTensor::record_rows(const Adam& adam, engine::Recorder& rec, uint32_t group, uint32_t tail_group, uint32_t row,
                             uint32_t head) const {
  if (grad_ == nullptr) throw std::logic_error(name_ + ": an Adam update needs its gradient");
  adam.record_rows(rec, group, tail_group, row, head, *param_, *grad_, m_, v_, static_cast<uint32_t>(floats_));
}

std::pair<std::string, std::string> AdamTensor::moment_names(MomentNames names) const {
  if (names == MomentNames::pytorch) return {name_ + ".exp_avg", name_ + ".exp_avg_sq"};
  return {name_ + ".adam_m", name_ + ".adam_v"};
}

std::vector<std::pair<std::string, std::vector<float>>> AdamTensor::download_moments(MomentNames names) const {
  const auto [m, v] = moment_names(names);
  return {{m, ctx_->download<float>(m_, floats_)}, {v, ctx_->download<float>(v_, floats_)}};
}

void AdamTensor::upload_moments(MomentNames names, const std::function<const std::vector<float>&(const std::string&)>& find,
                                const std::string& where) {
  const auto [m, v] = moment_names(names);
  for (auto [buffer, array] : {std::pair{&m_, m}, {&v_, v}}) {
    const std::vector<float>& values = find(array);
    if (values.size() != floats_)
      throw std::runtime_error(where + ": array '" + array + "' holds " + std::to_string(values.size()) + " floats, not " +
                               std::to_string(floats_));
    ctx_->upload(*buffer, std::span<const float>(values));
  }
}

void AdamTensor::zero_rows(const std::vector<uint32_t>& rows, size_t width) {
  for (engine::Buffer* b : {&m_, &v_}) {
    std::vector<float> values = ctx_->download<float>(*b, floats_);
    for (uint32_t r : rows) std::fill_n(values.begin() + static_cast<std::ptrdiff_t>(r * width), width, 0.0f);
    ctx_->upload(*b, std::span<const float>(values));
  }
}

}  // namespace s4d::optim
