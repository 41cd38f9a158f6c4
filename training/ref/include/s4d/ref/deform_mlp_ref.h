// CPU twin of the deformation MLP of deform_fwd / deform_bwd + deform_wgrad (ALGORITHMS.md 3.1 "Deformation
// decoder"): trunk Linear(F -> W) + trunk_extra x [ReLU, Linear(W -> W)], then per head
// ReLU -> Linear(W -> W) -> ReLU -> Linear(W -> out). Weight layout in shaders/shared/s4d_deform.h.
// Templated on the scalar type.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "s4d_deform.h"

namespace s4d::ref {

// Outputs of the heads, in head order (pos, scales, rotations, opacity, sh); empty for heads that are off.
template <class T>
using HeadValues = std::array<std::vector<T>, S4D_DEFORM_HEADS>;

namespace detail {

template <class T>
T relu(T x) { return x > T(0) ? x : T(0); }

// y = weight x + bias for the Linear(in -> out) at `offset`; the sum starts at the bias and runs over
// inputs in order, as in the kernels.
template <class T>
std::vector<T> linear(const std::vector<T>& mlp, uint32_t offset, uint32_t in, uint32_t out, const std::vector<T>& x) {
  std::vector<T> y(out);
  for (uint32_t o = 0; o < out; ++o) {
    T acc = mlp[offset + out * in + o];
    for (uint32_t i = 0; i < in; ++i) acc += mlp[offset + o * in + i] * x[i];
    y[o] = acc;
  }
  return y;
}

// Backward of linear() for cotangent v_y: adds the weight and bias gradients to v_mlp, returns v_x.
template <class T>
std::vector<T> linear_bwd(const std::vector<T>& mlp, uint32_t offset, uint32_t in, uint32_t out, const std::vector<T>& x,
                          const std::vector<T>& v_y, std::vector<T>& v_mlp) {
  std::vector<T> v_x(in, T(0));
  for (uint32_t o = 0; o < out; ++o) {
    v_mlp[offset + out * in + o] += v_y[o];
    for (uint32_t i = 0; i < in; ++i) {
      v_mlp[offset + o * in + i] += v_y[o] * x[i];
      v_x[i] += mlp[offset + o * in + i] * v_y[o];
    }
  }
  return v_x;
}

template <class T>
std::vector<T> relu_of(std::vector<T> x) {
  for (T& v : x) v = relu(v);
  return x;
}

// Trunk pre-activations: z[0] = Linear(F -> W)(feat), z[e] = Linear(W -> W)(relu(z[e - 1])).
template <class T>
std::vector<std::vector<T>> trunk_forward(const gpu::DeformShape& s, const std::vector<T>& mlp, const std::vector<T>& feat) {
  std::vector<std::vector<T>> z;
  z.push_back(linear(mlp, gpu::deform_trunk_offset(s, 0), gpu::deform_feat_dim(s), s.width, feat));
  for (uint32_t e = 1; e <= s.trunk_extra; ++e)
    z.push_back(linear(mlp, gpu::deform_trunk_offset(s, e), s.width, s.width, relu_of(z.back())));
  return z;
}

}  // namespace detail

// Head outputs for a feature vector.
template <class T>
HeadValues<T> deform_mlp_forward(const gpu::DeformShape& s, const std::vector<T>& mlp, const std::vector<T>& feat) {
  const std::vector<T> hidden = detail::relu_of(detail::trunk_forward(s, mlp, feat).back());
  HeadValues<T> out;
  const uint32_t W = s.width;
  for (uint32_t h = 0; h < S4D_DEFORM_HEADS; ++h) {
    if (!gpu::deform_head_on(s, h)) continue;
    const uint32_t o1 = gpu::deform_head_offset(s, h), o2 = o1 + gpu::deform_linear_floats(W, W);
    out[h] = detail::linear(mlp, o2, W, gpu::deform_head_out(h), detail::relu_of(detail::linear(mlp, o1, W, W, hidden)));
  }
  return out;
}

// Backward for head cotangents v_heads (entries of heads that are off are ignored): adds the weight
// and bias gradients to v_mlp, returns dL/d feat.
template <class T>
std::vector<T> deform_mlp_backward(const gpu::DeformShape& s, const std::vector<T>& mlp, const std::vector<T>& feat,
                                   const HeadValues<T>& v_heads, std::vector<T>& v_mlp) {
  const std::vector<std::vector<T>> z = detail::trunk_forward(s, mlp, feat);
  const std::vector<T> hidden = detail::relu_of(z.back());
  const uint32_t W = s.width;
  std::vector<T> v_z(W, T(0));  // dL/d trunk output, gathered over the heads
  for (uint32_t h = 0; h < S4D_DEFORM_HEADS; ++h) {
    if (!gpu::deform_head_on(s, h)) continue;
    const uint32_t o1 = gpu::deform_head_offset(s, h), o2 = o1 + gpu::deform_linear_floats(W, W);
    const std::vector<T> y1 = detail::linear(mlp, o1, W, W, hidden);
    std::vector<T> v_y1 = detail::linear_bwd(mlp, o2, W, gpu::deform_head_out(h), detail::relu_of(y1), v_heads[h], v_mlp);
    for (uint32_t i = 0; i < W; ++i) v_y1[i] = y1[i] > T(0) ? v_y1[i] : T(0);
    const std::vector<T> v_hidden = detail::linear_bwd(mlp, o1, W, W, hidden, v_y1, v_mlp);
    for (uint32_t i = 0; i < W; ++i) v_z[i] += z.back()[i] > T(0) ? v_hidden[i] : T(0);
  }
  for (uint32_t e = s.trunk_extra; e >= 1; --e) {
    std::vector<T> v_prev = detail::linear_bwd(mlp, gpu::deform_trunk_offset(s, e), W, W, detail::relu_of(z[e - 1]), v_z, v_mlp);
    for (uint32_t i = 0; i < W; ++i) v_prev[i] = z[e - 1][i] > T(0) ? v_prev[i] : T(0);
    v_z = v_prev;
  }
  return detail::linear_bwd(mlp, gpu::deform_trunk_offset(s, 0), gpu::deform_feat_dim(s), W, feat, v_z, v_mlp);
}

}  // namespace s4d::ref
