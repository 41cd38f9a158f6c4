// A Gaussian cloud being trained: its parameters in the rasterizer's layouts, their gradients, Adam's
// two moments, and the per-Gaussian densification statistics, all device-resident and all indexed by
// Gaussian so that densification (a gather over Gaussians) keeps every array consistent.
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "s4d/engine/buffer.h"
#include "s4d/engine/context.h"
#include "s4d/io/ply_gaussians.h"
#include "s4d/optim/adam_tensor.h"
#include "s4d/run/checkpoint.h"
#include "s4d/splat/gaussian_buffers.h"
#include "s4d/splat/rasterizer.h"

namespace s4d::model {

using splat::Attr;
// One array per trained tensor: the cloud's attributes (splat::kCloudAttrs, the Adam groups' order).
template <class T>
using CloudArrays = splat::PerAttr<T, splat::kCloudAttrCount>;

// Densification statistics (ALGORITHMS.md 2.2), one float per Gaussian each, named as checkpoints list them.
using run::Stat;
using enum run::Stat;
using run::stat_name;

// Everything per Gaussian for `count` Gaussians, on the host (checkpoints, tests).
struct HostState {
  io::GaussianCloud cloud;
  CloudArrays<std::vector<float>> m, v;  // Adam moments, same layouts as the parameters
  std::array<std::vector<float>, kStatCount> stats;
};

class TrainableGaussians {
 public:
  // Uploads `cloud`; moments and statistics start at zero. SH storage is fixed at cloud.sh_degree.
  TrainableGaussians(engine::Context& ctx, const io::GaussianCloud& cloud, std::string name = "gaussians");
  explicit TrainableGaussians(engine::Context& ctx, const HostState& state, std::string name = "gaussians");
  // Its Adam tensors point at its own buffers: it stays where it was made.
  TrainableGaussians(const TrainableGaussians&) = delete;
  TrainableGaussians& operator=(const TrainableGaussians&) = delete;

  uint32_t size() const { return count_; }
  int sh_degree() const { return sh_degree_; }  // stored degree
  uint32_t sh_coeffs() const { return static_cast<uint32_t>((sh_degree_ + 1) * (sh_degree_ + 1)); }
  uint32_t width(Attr a) const { return splat::attr_floats(a, sh_coeffs()); }  // floats per Gaussian

  engine::Buffer& param(Attr a) { return param_[a]; }
  engine::Buffer& grad(Attr a) { return grad_[a]; }
  engine::Buffer& moment1(Attr a) { return adam_[a].moment1(); }
  engine::Buffer& moment2(Attr a) { return adam_[a].moment2(); }
  // The attribute as Adam trains it: its parameter, gradient and moments (optim/adam_tensor.h).
  const optim::AdamTensor& adam(Attr a) const { return adam_[a]; }
  engine::Buffer& stat(Stat s) { return stat_[s]; }
  const engine::Buffer& param(Attr a) const { return param_[a]; }
  const engine::Buffer& stat(Stat s) const { return stat_[s]; }

  // Rasterizer views; `active_degree` is clamped to the stored degree.
  splat::GaussianParams params(int active_degree) const;
  splat::GaussianGrads grads();

  // Replaces every array with one for `count` Gaussians (the densifier's output). Each array in
  // `next` must hold count x width floats; grads are reallocated, not carried.
  struct Arrays {
    CloudArrays<engine::Buffer> param, m, v;
    std::array<engine::Buffer, kStatCount> stat;
  };
  void adopt(Arrays&& next, uint32_t count);
  // Fresh buffers for `count` Gaussians, named after this cloud; contents undefined.
  Arrays allocate(uint32_t count) const;

  HostState download() const;
  io::GaussianCloud download_cloud() const;
  engine::Context& context() const { return *ctx_; }

 private:
  void upload(const HostState& state);
  void allocate_grads();

  engine::Context* ctx_;
  std::string name_;
  uint32_t count_ = 0;
  int sh_degree_ = 0;
  CloudArrays<engine::Buffer> param_, grad_;
  CloudArrays<optim::AdamTensor> adam_;  // on param_ and grad_
  std::array<engine::Buffer, kStatCount> stat_;
};

}  // namespace s4d::model
