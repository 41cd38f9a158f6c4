#include "s4d/model/trainable_gaussians.h"

#include <stdexcept>
#include <utility>

#include "s4d/engine/buffer_from.h"

namespace s4d::model {

namespace {

using splat::cloud_arrays;
using splat::kCloudAttrs;

HostState zero_state(const io::GaussianCloud& cloud) {
  HostState s{cloud, {}, {}, {}};
  const auto arrays = cloud_arrays(cloud);
  for (Attr a : kCloudAttrs) {
    s.m[a].assign(arrays[a]->size(), 0.0f);
    s.v[a].assign(arrays[a]->size(), 0.0f);
  }
  for (auto& stat : s.stats) stat.assign(cloud.size(), 0.0f);
  return s;
}

}  // namespace

TrainableGaussians::TrainableGaussians(engine::Context& ctx, const io::GaussianCloud& cloud, std::string name)
    : TrainableGaussians(ctx, zero_state(cloud), std::move(name)) {}

TrainableGaussians::TrainableGaussians(engine::Context& ctx, const HostState& state, std::string name)
    : ctx_(&ctx), name_(std::move(name)), count_(static_cast<uint32_t>(state.cloud.size())), sh_degree_(state.cloud.sh_degree) {
  if (sh_degree_ < 0 || sh_degree_ > 3) throw std::invalid_argument(name_ + ": SH degree must be 0..3");
  upload(state);
}

void TrainableGaussians::upload(const HostState& state) {
  const auto arrays = cloud_arrays(state.cloud);
  for (Attr a : kCloudAttrs) {
    const size_t n = size_t{count_} * width(a);
    const std::string what = name_ + " " + splat::attr_name(a);
    if (arrays[a]->size() != n || state.m[a].size() != n || state.v[a].size() != n)
      throw std::invalid_argument(what + ": expected " + std::to_string(n) + " floats for " + std::to_string(count_) +
                                  " Gaussians in the parameters and both Adam moments");
    param_[a] = engine::buffer_from(*ctx_, what, *arrays[a]);
    adam_[a] = optim::AdamTensor(*ctx_, what, param_[a], &grad_[a], n, engine::buffer_from(*ctx_, what + " adam m", state.m[a]),
                                 engine::buffer_from(*ctx_, what + " adam v", state.v[a]));
  }
  for (uint32_t s = 0; s < kStatCount; ++s) {
    const std::string what = name_ + " " + stat_name(Stat(s));
    if (state.stats[s].size() != count_)
      throw std::invalid_argument(what + ": expected " + std::to_string(count_) + " values");
    stat_[s] = engine::buffer_from(*ctx_, what, state.stats[s]);
  }
  allocate_grads();
}

void TrainableGaussians::allocate_grads() {
  for (Attr a : kCloudAttrs)
    grad_[a] = engine::Buffer(*ctx_, name_ + " " + splat::attr_name(a) + " grad", size_t{count_} * width(a) * 4);
}

splat::GaussianParams TrainableGaussians::params(int active_degree) const {
  const int degree = active_degree < 0 ? sh_degree_ : std::min(active_degree, sh_degree_);
  splat::GaussianParams p{.count = count_, .sh_degree = static_cast<uint32_t>(degree), .sh_coeffs = sh_coeffs()};
  for (Attr a : kCloudAttrs) p[a] = &param_[a];
  return p;
}

splat::GaussianGrads TrainableGaussians::grads() {
  splat::GaussianGrads g;
  for (Attr a : kCloudAttrs) g[a] = &grad_[a];
  return g;
}

TrainableGaussians::Arrays TrainableGaussians::allocate(uint32_t count) const {
  Arrays out;
  for (Attr a : kCloudAttrs) {
    const size_t bytes = size_t{count} * width(a) * 4;
    const std::string what = name_ + " " + splat::attr_name(a);
    out.param[a] = engine::Buffer(*ctx_, what, bytes);
    out.m[a] = engine::Buffer(*ctx_, what + " adam m", bytes);
    out.v[a] = engine::Buffer(*ctx_, what + " adam v", bytes);
  }
  for (uint32_t s = 0; s < kStatCount; ++s) out.stat[s] = engine::Buffer(*ctx_, name_ + " " + stat_name(Stat(s)), size_t{count} * 4);
  return out;
}

void TrainableGaussians::adopt(Arrays&& next, uint32_t count) {
  for (Attr a : kCloudAttrs) {
    const size_t bytes = size_t{count} * width(a) * 4;
    for (const engine::Buffer* b : {&next.param[a], &next.m[a], &next.v[a]})
      if (b->size() != bytes)
        throw std::invalid_argument(name_ + ": adopted buffer '" + b->name() + "' holds " + std::to_string(b->size()) +
                                    " bytes, expected " + std::to_string(bytes));
  }
  for (const engine::Buffer& b : next.stat)
    if (b.size() != size_t{count} * 4)
      throw std::invalid_argument(name_ + ": adopted statistic '" + b.name() + "' has the wrong size");
  param_ = std::move(next.param);
  for (Attr a : kCloudAttrs)
    adam_[a] = optim::AdamTensor(*ctx_, name_ + " " + splat::attr_name(a), param_[a], &grad_[a], size_t{count} * width(a),
                                 std::move(next.m[a]), std::move(next.v[a]));
  stat_ = std::move(next.stat);
  count_ = count;
  allocate_grads();
}

HostState TrainableGaussians::download() const {
  HostState s;
  s.cloud.sh_degree = sh_degree_;
  const auto arrays = cloud_arrays(s.cloud);
  for (Attr a : kCloudAttrs) {
    const size_t n = size_t{count_} * width(a);
    *arrays[a] = ctx_->download<float>(param_[a], n);
    s.m[a] = ctx_->download<float>(adam_[a].moment1(), n);
    s.v[a] = ctx_->download<float>(adam_[a].moment2(), n);
  }
  for (uint32_t k = 0; k < kStatCount; ++k) s.stats[k] = ctx_->download<float>(stat_[k], count_);
  return s;
}

io::GaussianCloud TrainableGaussians::download_cloud() const {
  io::GaussianCloud c;
  c.sh_degree = sh_degree_;
  const auto arrays = cloud_arrays(c);
  for (Attr a : kCloudAttrs) *arrays[a] = ctx_->download<float>(param_[a], size_t{count_} * width(a));
  return c;
}

}  // namespace s4d::model
