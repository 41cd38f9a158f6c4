// CPU twins of the CCPL kernels (nn_ccpl_gather(_bwd), nn_l2norm_cols(_bwd), nn_patchnce; layouts in
// shaders/shared/s4d_nn_ccpl.h) and of one level of the whole CCPL term as training/kernels/nn/ccpl.cpp
// records it: difference vectors of the sampled (anchor, neighbour) pairs of q's and k's features,
// the projection head Linear(C, C) - ReLU - Linear(C, C / 4) on each column, L2 normalisation,
// PatchNCE with temperature tau. Templated on the scalar type; tests check the backward against
// finite differences in double and the float kernels against these.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "s4d/ref/nn_grad_ref.h"

namespace s4d::ref {

// [c, 1, s]: f[:, anchor[s]] - f[:, neighbour[s]] (flat indices into f's h x w plane).
template <class T>
Chw<T> ccpl_gather(const Chw<T>& f, const std::vector<uint32_t>& anchor, const std::vector<uint32_t>& neighbour) {
  const auto s = static_cast<uint32_t>(anchor.size());
  const size_t plane = size_t{f.h} * f.w;
  Chw<T> out(f.c, 1, s);
  for (uint32_t c = 0; c < f.c; ++c)
    for (uint32_t k = 0; k < s; ++k) out.v[size_t{c} * s + k] = f.v[c * plane + anchor[k]] - f.v[c * plane + neighbour[k]];
  return out;
}

// The adjoint of ccpl_gather: [c, h, w].
template <class T>
Chw<T> ccpl_gather_bwd(const Chw<T>& dout, const std::vector<uint32_t>& anchor, const std::vector<uint32_t>& neighbour,
                       uint32_t h, uint32_t w) {
  const size_t plane = size_t{h} * w, s = anchor.size();
  Chw<T> df(dout.c, h, w);
  for (uint32_t c = 0; c < dout.c; ++c)
    for (size_t k = 0; k < s; ++k) {
      df.v[c * plane + anchor[k]] += dout.v[c * s + k];
      df.v[c * plane + neighbour[k]] -= dout.v[c * s + k];
    }
  return df;
}

// Each column of x [c, 1, s] divided by its norm + 1e-7.
template <class T>
Chw<T> l2norm_cols(const Chw<T>& x) {
  const size_t s = size_t{x.h} * x.w;
  Chw<T> y = x;
  for (size_t k = 0; k < s; ++k) {
    T squares = 0;
    for (uint32_t c = 0; c < x.c; ++c) squares += x.v[c * s + k] * x.v[c * s + k];
    const T d = std::sqrt(squares) + T(1e-7);
    for (uint32_t c = 0; c < x.c; ++c) y.v[c * s + k] /= d;
  }
  return y;
}

// dL/dx of l2norm_cols given dy.
template <class T>
Chw<T> l2norm_cols_bwd(const Chw<T>& x, const Chw<T>& dy) {
  const size_t s = size_t{x.h} * x.w;
  Chw<T> dx(x.c, x.h, x.w);
  for (size_t k = 0; k < s; ++k) {
    T squares = 0, dot = 0;
    for (uint32_t c = 0; c < x.c; ++c) squares += x.v[c * s + k] * x.v[c * s + k], dot += x.v[c * s + k] * dy.v[c * s + k];
    const T n = std::sqrt(squares), d = n + T(1e-7), f = n > 0 ? dot / (n * d * d) : T(0);
    for (uint32_t c = 0; c < x.c; ++c) dx.v[c * s + k] = dy.v[c * s + k] / d - x.v[c * s + k] * f;
  }
  return dx;
}

// nn_patchnce's outputs for scores [s, s]: loss[i] = logsumexp_j(P[i, j] inv_tau) - P[i, i] inv_tau
// and grad = d(scale sum_i loss[i]) / dP.
template <class T>
struct PatchNceRef {
  std::vector<T> loss, grad;
};
template <class T>
PatchNceRef<T> patchnce_rows(const std::vector<T>& scores, uint32_t s, T inv_tau, T scale) {
  PatchNceRef<T> r{std::vector<T>(s), std::vector<T>(size_t{s} * s)};
  for (uint32_t i = 0; i < s; ++i) {
    const T* row = &scores[size_t{i} * s];
    T top = row[0] * inv_tau, others = 0;
    for (uint32_t j = 1; j < s; ++j) top = std::max(top, row[j] * inv_tau);
    for (uint32_t j = 0; j < s; ++j)
      if (j != i) others += std::exp(row[j] * inv_tau - top);
    const T sum = std::exp(row[i] * inv_tau - top) + others, g = scale * inv_tau / sum;
    r.loss[i] = std::log(sum) + top - row[i] * inv_tau;
    for (uint32_t j = 0; j < s; ++j) r.grad[size_t{i} * s + j] = j == i ? -g * others : g * std::exp(row[j] * inv_tau - top);
  }
  return r;
}

// One projection head: Linear(c, c) - ReLU - Linear(c, out), weights [out, in].
template <class T>
struct CcplHeadRef {
  uint32_t c = 0, out = 0;
  std::vector<T> w1, b1, w2, b2;
};

// The head's gradients (w1, b1, w2, b2) and the gradient of q's features.
template <class T>
struct CcplGradsRef {
  Chw<T> dfq;
  ConvGradsRef<T> first, second;
};

// One level of CCPL: weight * mean_i PatchNCE_i of the normalised head outputs of q's and k's
// difference vectors. Its gradient w.r.t. q's features and, where `k_in_heads`, the heads' gradient
// through both q and k (CCPL's heads see k undetached); otherwise through q only.
template <class T>
struct CcplLevelRef {
  T value = 0;
  CcplGradsRef<T> grads;
};
template <class T>
CcplLevelRef<T> ccpl_level(const Chw<T>& fq, const Chw<T>& fk, const std::vector<uint32_t>& anchor,
                           const std::vector<uint32_t>& neighbour, const CcplHeadRef<T>& head, T tau, T weight,
                           bool k_in_heads) {
  const auto s = static_cast<uint32_t>(anchor.size());
  struct Side {
    Chw<T> diff, hidden, proj, z;
  };
  auto forward = [&](const Chw<T>& f) {
    Side side;
    side.diff = ccpl_gather(f, anchor, neighbour);
    side.hidden = conv1x1(side.diff, head.w1, head.b1, head.c, true);
    side.proj = conv1x1(side.hidden, head.w2, head.b2, head.out, false);
    side.z = l2norm_cols(side.proj);
    return side;
  };
  const Side q = forward(fq), k = forward(fk);
  std::vector<T> scores(size_t{s} * s, T(0));
  for (uint32_t i = 0; i < s; ++i)
    for (uint32_t j = 0; j < s; ++j)
      for (uint32_t d = 0; d < head.out; ++d) scores[size_t{i} * s + j] += q.z.v[size_t{d} * s + i] * k.z.v[size_t{d} * s + j];
  const PatchNceRef<T> nce = patchnce_rows(scores, s, T(1) / tau, weight / T(s));
  CcplLevelRef<T> r;
  for (const T l : nce.loss) r.value += weight * l / T(s);
  Chw<T> dzq(head.out, 1, s), dzk(head.out, 1, s);
  for (uint32_t i = 0; i < s; ++i)
    for (uint32_t j = 0; j < s; ++j)
      for (uint32_t d = 0; d < head.out; ++d) {
        dzq.v[size_t{d} * s + i] += nce.grad[size_t{i} * s + j] * k.z.v[size_t{d} * s + j];
        dzk.v[size_t{d} * s + j] += nce.grad[size_t{i} * s + j] * q.z.v[size_t{d} * s + i];
      }
  auto backward = [&](const Side& side, const Chw<T>& dz, CcplGradsRef<T>& g) {
    const Chw<T> dproj = l2norm_cols_bwd(side.proj, dz);
    const ConvGradsRef<T> g2 = conv_wgrad(side.hidden, dproj, 1);
    const Chw<T> dhidden = relu_bwd(conv1x1_bwd_input(dproj, head.w2, head.c), side.hidden);
    const ConvGradsRef<T> g1 = conv_wgrad(side.diff, dhidden, 1);
    auto add = [](ConvGradsRef<T>& into, const ConvGradsRef<T>& from) {
      if (into.weight.empty()) into = from;
      else {
        for (size_t e = 0; e < from.weight.size(); ++e) into.weight[e] += from.weight[e];
        for (size_t e = 0; e < from.bias.size(); ++e) into.bias[e] += from.bias[e];
      }
    };
    add(g.first, g1);
    add(g.second, g2);
    return conv1x1_bwd_input(dhidden, head.w1, head.c);
  };
  r.grads.dfq = ccpl_gather_bwd(backward(q, dzq, r.grads), anchor, neighbour, fq.h, fq.w);
  if (k_in_heads) backward(k, dzk, r.grads);
  return r;
}

}  // namespace s4d::ref
