// CPU twin of adam_step (shaders/optim/adam_step.comp): PyTorch's Adam with bias correction.
#pragma once
#include <cmath>
#include <vector>

namespace s4d::ref {

struct AdamHyper {
  double lr = 1e-3, beta1 = 0.9, beta2 = 0.999, eps = 1e-15;
};

// One update at step t (1-based), in place.
template <class T>
void adam_step(std::vector<T>& params, const std::vector<T>& grads, std::vector<T>& m, std::vector<T>& v,
               const AdamHyper& h, int t) {
  const T b1 = T(h.beta1), b2 = T(h.beta2);
  const T inv_bias1 = T(1 / (1 - std::pow(h.beta1, t))), inv_sqrt_bias2 = T(1 / std::sqrt(1 - std::pow(h.beta2, t)));
  for (size_t i = 0; i < params.size(); ++i) {
    m[i] = b1 * m[i] + (1 - b1) * grads[i];
    v[i] = b2 * v[i] + (1 - b2) * grads[i] * grads[i];
    params[i] -= T(h.lr) * (m[i] * inv_bias1) / (std::sqrt(v[i]) * inv_sqrt_bias2 + T(h.eps));
  }
}

}  // namespace s4d::ref
