// CPU twins of the training loss and Adam: the loss gradient against central finite differences in
// double, identities of SSIM, and Adam's first step.
#include <doctest/doctest.h>

#include <cmath>
#include <random>
#include <vector>

#include "s4d/optim/lr_schedule.h"
#include "s4d/ref/adam_ref.h"
#include "s4d/ref/loss_ref.h"

namespace {

std::vector<double> random_image(size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<double> v(n);
  for (double& x : v) x = u(rng);
  return v;
}

}  // namespace

TEST_CASE("loss gradient matches central finite differences in double") {
  const int w = 13, h = 9, c = 3;  // smaller than the 11x11 window in one axis: borders everywhere
  const size_t n = static_cast<size_t>(w * h * c);
  std::vector<double> x = random_image(n, 1);
  const std::vector<double> y = random_image(n, 2);
  const auto value = s4d::ref::l1_ssim_loss(x, y, w, h, c, 0.2);
  double worst = 0;
  for (size_t e = 0; e < n; ++e) {
    const double step = 1e-6, saved = x[e];
    x[e] = saved + step;
    const double lp = s4d::ref::l1_ssim_loss(x, y, w, h, c, 0.2).loss;
    x[e] = saved - step;
    const double lm = s4d::ref::l1_ssim_loss(x, y, w, h, c, 0.2).loss;
    x[e] = saved;
    worst = std::max(worst, std::abs((lp - lm) / (2 * step) - value.grad[e]));
  }
  // Gradients are ~1/n = 3e-3 in size; central differences in double leave ~1e-10 (measured 3e-11).
  CHECK(worst < 1e-8);
}

TEST_CASE("SSIM of an image with itself is 1 and the loss and its gradient vanish") {
  const std::vector<double> x = random_image(20 * 17 * 3, 3);
  const auto v = s4d::ref::l1_ssim_loss(x, x, 20, 17, 3, 0.2);
  CHECK(v.ssim == doctest::Approx(1.0).epsilon(1e-12));  // a1 = b1 and a2 = b2 exactly
  CHECK(v.loss == doctest::Approx(0.0));
  for (double g : v.grad) REQUIRE(std::abs(g) < 1e-12);
}

TEST_CASE("SSIM of two constant images has the closed form, zero padding included") {
  // For constants a and b, a pixel whose window keeps the fraction s of its weight inside the image
  // sees mu_x = a s, E[x^2] = a^2 s, E[xy] = a b s, so sigma_x^2 = a^2 s (1 - s), sigma_xy = a b s (1 - s):
  // S = (2ab s^2 + C1)/((a^2 + b^2) s^2 + C1) * (2ab s(1-s) + C2)/((a^2 + b^2) s(1-s) + C2),
  // with s = sx(x) sy(y) the product of the inside tap sums. Computed here without any filtering.
  const int w = 23, h = 17;
  const double a = 0.3, b = 0.7, c1 = 1e-4, c2 = 9e-4;
  const double taps[6] = {0.26601172486179436, 0.21300553771125369, 0.10936068950970002,
                          0.036000772128430829, 0.007598758135239185, 0.0010283800844791101};
  auto inside = [&](int i, int size) {
    double sum = 0;
    for (int k = -5; k <= 5; ++k)
      if (i + k >= 0 && i + k < size) sum += taps[std::abs(k)];
    return sum;
  };
  double expected = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const double sv = inside(x, w) * inside(y, h), var = sv * (1 - sv);
      expected += (2 * a * b * sv * sv + c1) / ((a * a + b * b) * sv * sv + c1) * (2 * a * b * var + c2) /
                  ((a * a + b * b) * var + c2);
    }
  expected /= w * h;
  const std::vector<double> x(static_cast<size_t>(w * h), a), y(static_cast<size_t>(w * h), b);
  const auto v = s4d::ref::l1_ssim_loss(x, y, w, h, 1, 1.0);
  CHECK(v.ssim == doctest::Approx(expected).epsilon(1e-12));  // same maths, different order: ~1e-16
  CHECK(v.l1 == doctest::Approx(b - a));
  CHECK(v.loss == doctest::Approx(1 - expected).epsilon(1e-12));
}

TEST_CASE("TV gradient matches central finite differences in double; constant images have none") {
  const s4d::ref::LossShape shape{7, 5, 3};
  std::vector<double> x = random_image(shape.n(), 3);
  const auto [value, grad] = s4d::ref::tv_loss(x, shape, 0.7);
  CHECK(value > 0);
  double worst = 0;
  for (size_t e = 0; e < x.size(); ++e) {
    const double step = 1e-6, saved = x[e];
    x[e] = saved + step;
    const double lp = s4d::ref::tv_loss(x, shape, 0.7).first;
    x[e] = saved - step;
    const double lm = s4d::ref::tv_loss(x, shape, 0.7).first;
    x[e] = saved;
    worst = std::max(worst, std::abs((lp - lm) / (2 * step) - grad[e]));
  }
  CHECK(worst < 1e-8);  // a quadratic: central differences are exact up to rounding, measured 1.7e-11
  const auto flat = s4d::ref::tv_loss(std::vector<double>(shape.n(), 0.25), shape, 0.7);
  CHECK(flat.first == 0);
  for (double g : flat.second) CHECK(g == 0);
}

TEST_CASE("Adam's first step moves every parameter by lr against the gradient's sign") {
  std::vector<double> p = {1.0, -2.0, 0.5}, g = {0.3, -4.0, 1e-3}, m(3, 0.0), v(3, 0.0);
  s4d::ref::adam_step(p, g, m, v, {.lr = 0.01, .beta1 = 0.9, .beta2 = 0.999, .eps = 1e-15}, 1);
  // t = 1: m_hat = g, v_hat = g^2, so the step is lr * g / (|g| + eps) = lr * sign(g).
  CHECK(p[0] == doctest::Approx(0.99).epsilon(1e-12));
  CHECK(p[1] == doctest::Approx(-1.99).epsilon(1e-12));
  CHECK(p[2] == doctest::Approx(0.49).epsilon(1e-9));
}

TEST_CASE("the position learning rate decays log-linearly and holds at the end") {
  const s4d::optim::LogLinearSchedule s{.lr0 = 1.6e-4, .lr1 = 1.6e-6, .max_steps = 20000};
  CHECK(s.at(0) == doctest::Approx(1.6e-4).epsilon(1e-12));
  CHECK(s.at(10000) == doctest::Approx(1.6e-5).epsilon(1e-12));  // geometric mean halfway
  CHECK(s.at(20000) == doctest::Approx(1.6e-6).epsilon(1e-12));
  CHECK(s.at(50000) == doctest::Approx(1.6e-6).epsilon(1e-12));
  CHECK(s4d::optim::LogLinearSchedule{.lr0 = 0, .lr1 = 1e-3, .max_steps = 10}.at(5) == 0.0);
}
