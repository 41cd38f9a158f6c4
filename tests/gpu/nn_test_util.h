// Helpers of the network-layer tests: seeded random tensors and weights (values away from
// denormals, which lavapipe may flush), float -> double copies for the double twins, upload of a
// twin tensor (comparisons go through expect_allclose.h).
#pragma once
#include <doctest/doctest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "s4d/engine/recorder.h"
#include "s4d/nn/layers.h"
#include "s4d/nn/tensor.h"
#include "expect_allclose.h"
#include "s4d/ref/nn_ref.h"
#include "test_context.h"

namespace s4d::test {

// Records `f` into one command buffer, runs it and returns what it returned.
template <class F>
auto run(F&& f) {
  engine::Recorder rec(context(), "nn test");
  auto out = f(rec);
  context().run(std::move(rec));
  return out;
}

inline std::vector<float> random_values(size_t n, float lo, float hi, std::mt19937& rng) {
  std::uniform_real_distribution<float> u(lo, hi);
  std::vector<float> v(n);
  for (float& e : v) e = u(rng);
  return v;
}

inline ref::Chw<float> random_chw(uint32_t c, uint32_t h, uint32_t w, std::mt19937& rng, float lo = -1.0f,
                                  float hi = 1.0f) {
  ref::Chw<float> t(c, h, w);
  t.v = random_values(t.v.size(), lo, hi, rng);
  return t;
}

inline std::vector<double> to_double(const std::vector<float>& v) { return {v.begin(), v.end()}; }

inline ref::Chw<double> to_double(const ref::Chw<float>& t) {
  ref::Chw<double> d(t.c, t.h, t.w);
  d.v = to_double(t.v);
  return d;
}

inline nn::Tensor upload(const ref::Chw<float>& t, const std::string& name = "x") {
  return nn::upload_tensor(context(), name, t.c, t.h, t.w, t.v);
}

// A device tensor's values as a double twin tensor (the twin then starts from what the GPU holds).
inline ref::Chw<double> download_chw(const nn::Tensor& t) {
  ref::Chw<double> d(t.c, t.h, t.w);
  d.v = to_double(nn::download(context(), t));
  return d;
}

// A layer's random parameters: He-uniform weights (+-sqrt(6 / fan_in)), so activations keep their
// scale and their spatial variation through deep ReLU stacks (PyTorch's default +-1/sqrt(fan_in)
// shrinks them about 6x per layer and leaves relu4_1 of a random VGG nearly constant per channel),
// and small biases.
struct ConvParams {
  uint32_t cin = 0, cout = 0, k = 1;
  std::vector<float> weight, bias;
  bool linear = false;  // a Linear layer: weight [cout, cin] in files
};

inline ConvParams random_conv(uint32_t cin, uint32_t cout, uint32_t k, std::mt19937& rng) {
  const float bound = std::sqrt(6.0f / static_cast<float>(cin * k * k));
  return {cin, cout, k, random_values(size_t{cout} * cin * k * k, -bound, bound, rng),
          random_values(cout, -0.1f, 0.1f, rng)};
}

inline nn::ConvWeights upload(const ConvParams& c, const std::string& name = "w") {
  return nn::upload_conv(context(), name, c.cin, c.cout, c.k, c.weight, c.bias);
}

}  // namespace s4d::test
