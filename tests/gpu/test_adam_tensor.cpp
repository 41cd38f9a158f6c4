// optim::AdamTensor, every trainer's trained tensor: its updates are Adam's (the twin's), its moments
// survive a checkpoint under either naming scheme, a wrong size is refused by name, and a reset
// zeroes exactly the rows asked for.
#include <doctest/doctest.h>

#include <map>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "expect_allclose.h"
#include "s4d/engine/buffer_from.h"
#include "s4d/optim/adam_tensor.h"
#include "s4d/ref/adam_ref.h"
#include "test_context.h"

namespace {

using namespace s4d;

std::vector<float> random_values(size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1, 1);
  std::vector<float> v(n);
  for (float& x : v) x = u(rng);
  return v;
}

}  // namespace

TEST_CASE("AdamTensor: updates match the twin, with its own gradient or one named per update") {
  const size_t n = 500;
  std::vector<float> p = random_values(n, 1);
  engine::Buffer param = engine::buffer_from(test::context(), "p", p);
  engine::Buffer grad = engine::buffer_from(test::context(), "g", std::vector<float>(n, 0));
  optim::AdamTensor t(test::context(), "p", param, &grad, n);
  std::vector<double> pd(p.begin(), p.end()), m(n), v(n);
  optim::Adam adam(test::context(), 1);
  const optim::AdamSettings s{.lr = 0.01};
  for (uint32_t step = 1; step <= 4; ++step) {
    const std::vector<float> g = random_values(n, 10 + step);
    adam.set_group(0, s, step);
    adam.upload();
    engine::Recorder rec(test::context(), "adam tensor");
    engine::Buffer fresh = engine::buffer_from(test::context(), "fresh g", g);
    if (step % 2 == 1) {
      test::context().upload(grad, std::span<const float>(g));
      t.record(adam, rec, 0);
    } else {
      t.record(adam, rec, 0, fresh);
    }
    test::context().run(std::move(rec));
    ref::adam_step(pd, std::vector<double>(g.begin(), g.end()), m, v, {s.lr, s.beta1, s.beta2, s.eps}, static_cast<int>(step));
  }
  // Float vs double over 4 steps of size 0.01: measured 3e-8.
  test::expect_allclose(test::context().download<float>(param, n), pd, {.atol = 1e-5}, "param");
  test::expect_allclose(test::context().download<float>(t.moment1(), n), m, {.atol = 1e-6}, "adam m");
  test::expect_allclose(test::context().download<float>(t.moment2(), n), v, {.atol = 1e-6}, "adam v");

  optim::AdamTensor no_grad(test::context(), "q", param, nullptr, n);
  engine::Recorder rec(test::context(), "no gradient");
  CHECK_THROWS_WITH_AS(no_grad.record(adam, rec, 0), "q: an Adam update needs its gradient", std::logic_error);
}

TEST_CASE("AdamTensor: moments round-trip under the trainer's and PyTorch's names, and a wrong size is refused") {
  const size_t n = 12;
  engine::Buffer param = engine::buffer_from(test::context(), "p", std::vector<float>(n, 0));
  optim::AdamTensor t(test::context(), "field.planes", param, nullptr, n);
  CHECK(t.moment_names(optim::MomentNames::trainer) == std::pair<std::string, std::string>{"field.planes.adam_m", "field.planes.adam_v"});
  CHECK(t.moment_names(optim::MomentNames::pytorch) == std::pair<std::string, std::string>{"field.planes.exp_avg", "field.planes.exp_avg_sq"});
  for (const optim::MomentNames names : {optim::MomentNames::trainer, optim::MomentNames::pytorch}) {
    const auto [mn, vn] = t.moment_names(names);
    const std::map<std::string, std::vector<float>> file = {{mn, random_values(n, 5)}, {vn, random_values(n, 6)}};
    t.upload_moments(names, [&](const std::string& k) -> const std::vector<float>& { return file.at(k); }, "file");
    const auto back = t.download_moments(names);
    REQUIRE(back.size() == 2);
    CHECK(back[0].first == mn);
    CHECK(back[0].second == file.at(mn));
    CHECK(back[1].first == vn);
    CHECK(back[1].second == file.at(vn));
  }
  const std::vector<float> short_array(n - 1, 0);
  CHECK_THROWS_WITH_AS(t.upload_moments(optim::MomentNames::trainer,
                                        [&](const std::string&) -> const std::vector<float>& { return short_array; }, "ckpt"),
                       "ckpt: array 'field.planes.adam_m' holds 11 floats, not 12", std::runtime_error);
}

TEST_CASE("AdamTensor: zero_rows clears those rows' moments and nothing else") {
  const size_t rows = 5, width = 3, n = rows * width;
  engine::Buffer param = engine::buffer_from(test::context(), "p", std::vector<float>(n, 0));
  optim::AdamTensor t(test::context(), "sh_delta", param, nullptr, n);
  const std::vector<float> m = random_values(n, 7), v = random_values(n, 8);
  const std::map<std::string, std::vector<float>> file = {{"sh_delta.adam_m", m}, {"sh_delta.adam_v", v}};
  t.upload_moments(optim::MomentNames::trainer, [&](const std::string& k) -> const std::vector<float>& { return file.at(k); }, "file");
  t.zero_rows({3, 1}, width);
  const std::vector<float> m_after = test::context().download<float>(t.moment1(), n), v_after = test::context().download<float>(t.moment2(), n);
  for (size_t i = 0; i < n; ++i) {
    const bool cleared = i / width == 1 || i / width == 3;
    CHECK(m_after[i] == (cleared ? 0.0f : m[i]));
    CHECK(v_after[i] == (cleared ? 0.0f : v[i]));
  }
}
