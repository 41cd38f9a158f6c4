// Central finite differences in double for the CPU twins' backward passes (STYLE.md 6, tier 0):
// a directional derivative against (L(x + h d) - L(x - h d)) / 2h with a relative step, and the
// tangent directions of a quaternion (the twins normalise, so only those are meaningful).
#pragma once
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

namespace s4d::test {

// Compares an analytic directional derivative with a central difference of `loss` along `dir`
// applied to `param`; returns the error relative to the rule atol + rtol*scale.
struct FdChecker {
  double atol = 1e-6, rtol = 1e-5;
  double worst_ratio = 0;  // max |an - num| / (atol + rtol*max(|an|, |num|)); must stay <= 1
  double worst_abs = 0;

  void check(std::vector<double>& param, const std::vector<double>& dir, double analytic,
             const std::function<double()>& loss, const std::string& what) {
    double mag = 0;
    for (size_t k = 0; k < param.size(); ++k)
      if (dir[k] != 0) mag = std::max(mag, std::abs(param[k]));
    const double h = 1e-6 * std::max(1.0, mag);
    const std::vector<double> saved = param;
    for (size_t k = 0; k < param.size(); ++k) param[k] = saved[k] + h * dir[k];
    const double lp = loss();
    for (size_t k = 0; k < param.size(); ++k) param[k] = saved[k] - h * dir[k];
    const double lm = loss();
    param = saved;
    const double numeric = (lp - lm) / (2 * h);
    const double err = std::abs(analytic - numeric);
    const double ratio = err / (atol + rtol * std::max(std::abs(analytic), std::abs(numeric)));
    worst_ratio = std::max(worst_ratio, ratio), worst_abs = std::max(worst_abs, err);
    if (ratio > 1) FAIL_CHECK(what << ": analytic " << analytic << " numeric " << numeric);
  }

  // Every component of a flat parameter array.
  void check_all(std::vector<double>& param, const std::vector<double>& grad, const std::function<double()>& loss,
                 const std::string& name) {
    REQUIRE(grad.size() == param.size());
    for (size_t k = 0; k < param.size(); ++k) {
      std::vector<double> dir(param.size(), 0.0);
      dir[k] = 1;
      check(param, dir, grad[k], loss, name + "[" + std::to_string(k) + "]");
    }
  }
};

// Sum of a[i] * b[i].
inline double dot(const std::vector<double>& a, const std::vector<double>& b) {
  double s = 0;
  for (size_t i = 0; i < a.size(); ++i) s += a[i] * b[i];
  return s;
}

// Largest |analytic - central difference| of d/dv[i] sum(r * f(v)) over all i, relative to the
// largest |analytic| (step 1e-6; the nn twins' checks).
inline double fd_error(std::vector<double>& v, const std::function<std::vector<double>()>& f,
                       const std::vector<double>& r, const std::vector<double>& analytic) {
  REQUIRE(analytic.size() == v.size());
  double worst = 0, scale = 1e-30;
  for (size_t i = 0; i < v.size(); ++i) {
    const double step = 1e-6, saved = v[i];
    v[i] = saved + step;
    const double lp = dot(r, f());
    v[i] = saved - step;
    const double lm = dot(r, f());
    v[i] = saved;
    worst = std::max(worst, std::abs((lp - lm) / (2 * step) - analytic[i]));
    scale = std::max(scale, std::abs(analytic[i]));
  }
  return worst / scale;
}

// Three unit directions orthogonal to q (Gram-Schmidt on the axes, dropping the most parallel one).
inline std::vector<std::array<double, 4>> quat_tangents(const double* q) {
  std::vector<std::array<double, 4>> basis;
  std::array<double, 4> qn = {q[0], q[1], q[2], q[3]};
  const double n = std::sqrt(qn[0] * qn[0] + qn[1] * qn[1] + qn[2] * qn[2] + qn[3] * qn[3]);
  for (double& x : qn) x /= n;
  basis.push_back(qn);
  for (int axis = 0; axis < 4 && basis.size() < 4; ++axis) {
    std::array<double, 4> v{};
    v[static_cast<size_t>(axis)] = 1;
    for (const auto& b : basis) {
      const double d = v[0] * b[0] + v[1] * b[1] + v[2] * b[2] + v[3] * b[3];
      for (size_t k = 0; k < 4; ++k) v[k] -= d * b[k];
    }
    const double len = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2] + v[3] * v[3]);
    if (len < 0.3) continue;
    for (double& x : v) x /= len;
    basis.push_back(v);
  }
  return {basis.begin() + 1, basis.end()};
}

}  // namespace s4d::test
