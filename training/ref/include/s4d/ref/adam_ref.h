// CPU twin of adam_step (shaders/optim/adam_step.comp): PyTorch's Adam with bias correction.
#pragma once
#include <cmath>
#include <vector>

#include "s4d_optim.h"

namespace s4d::ref {

struct AdamHyper {
  double lr = 1e-3, beta1 = 0.9, beta2 = 0.999, eps = 1e-15;
};

template <class T>
void adam_update(T& p, T g, T& m, T& v, const AdamHyper& h, int t) {
  if (std::abs(g) > T(S4D_ADAM_MAX_GRAD)) g = std::copysign(T(S4D_ADAM_MAX_GRAD), g);
  const T b1 = T(h.beta1), b2 = T(h.beta2);
  const T inv_bias1 = T(1 / (1 - std::pow(h.beta1, t))), inv_sqrt_bias2 = T(1 / std::sqrt(1 - std::pow(h.beta2, t)));
  m = b1 * m + (1 - b1) * g;
  v = b2 * v + (1 - b2) * g * g;
  p -= T(h.lr) * (m * inv_bias1) / (std::sqrt(v) * inv_sqrt_bias2 + T(h.eps));
}

// One update at step t (1-based), in place.
template <class T>
void adam_step(std::vector<T>& params, const std::vector<T>& grads, std::vector<T>& m, std::vector<T>& v,
               const AdamHyper& h, int t) {
  for (size_t i = 0; i < params.size(); ++i) adam_update(params[i], grads[i], m[i], v[i], h, t);
}

// adam_step for rows of `row` elements whose first `head` use `h_head` and the rest `h_tail`.
template <class T>
void adam_step_rows(std::vector<T>& params, const std::vector<T>& grads, std::vector<T>& m, std::vector<T>& v,
                    size_t row, size_t head, const AdamHyper& h_head, const AdamHyper& h_tail, int t) {
  for (size_t i = 0; i < params.size(); ++i) adam_update(params[i], grads[i], m[i], v[i], i % row < head ? h_head : h_tail, t);
}

}  // namespace s4d::ref
