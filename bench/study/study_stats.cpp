#include "s4d/study/study_stats.h"

#include <algorithm>
#include <cmath>
#include <functional>

namespace s4d::study {

Interval wilson_interval(int wins, int n) {
  if (n <= 0) return {0, 1};
  const double z = 1.959963984540054, z2 = z * z, p = static_cast<double>(wins) / n;
  const double denom = 1 + z2 / n;
  const double centre = (p + z2 / (2.0 * n)) / denom;
  const double half = z / denom * std::sqrt(p * (1 - p) / n + z2 / (4.0 * n * n));
  return {std::max(0.0, centre - half), std::min(1.0, centre + half)};
}

BradleyTerry bradley_terry(const std::vector<std::vector<int>>& wins, const std::vector<std::string>& names) {
  const size_t m = names.size();
  BradleyTerry out;
  // The fit exists iff the "beat" graph is strongly connected: every method reaches every other.
  auto reach = [&](size_t from, bool forward) {
    std::vector<bool> seen(m, false);
    std::vector<size_t> stack = {from};
    seen[from] = true;
    while (!stack.empty()) {
      const size_t i = stack.back();
      stack.pop_back();
      for (size_t j = 0; j < m; ++j)
        if (!seen[j] && (forward ? wins[i][j] : wins[j][i]) > 0) seen[j] = true, stack.push_back(j);
    }
    return seen;
  };
  if (m < 2) {
    out.why = "fewer than two methods";
    return out;
  }
  const std::vector<bool> beaten_by_0 = reach(0, true), beating_0 = reach(0, false);
  for (size_t j = 0; j < m; ++j)
    if (!beaten_by_0[j] || !beating_0[j]) {
      const std::string& loser = !beating_0[j] ? names[j] : names[0];
      const std::string& other = !beating_0[j] ? names[0] : names[j];
      out.why = "no maximum-likelihood fit: " + loser + " never beats " + other +
                ", directly or through other methods (a method that never wins, or methods never compared)";
      return out;
    }
  std::vector<double> p(m, 1.0 / static_cast<double>(m)), w(m, 0);
  for (size_t i = 0; i < m; ++i)
    for (size_t j = 0; j < m; ++j) w[i] += wins[i][j];
  for (out.iterations = 1; out.iterations <= 100000; ++out.iterations) {
    std::vector<double> next(m);
    for (size_t i = 0; i < m; ++i) {
      double denom = 0;
      for (size_t j = 0; j < m; ++j)
        if (j != i && wins[i][j] + wins[j][i] > 0) denom += (wins[i][j] + wins[j][i]) / (p[i] + p[j]);
      next[i] = w[i] / denom;
    }
    double total = 0, change = 0;
    for (double v : next) total += v;
    for (size_t i = 0; i < m; ++i) {
      next[i] /= total;
      change = std::max(change, std::abs(next[i] - p[i]) / p[i]);
    }
    p = next;
    if (change < 1e-12) break;
  }
  out.strength = p;
  return out;
}

std::optional<double> krippendorff_alpha_nominal(const std::vector<std::vector<std::string>>& units) {
  std::map<std::string, std::map<std::string, double>> o;  // the coincidence matrix
  for (const auto& u : units) {
    const size_t mu = u.size();
    if (mu < 2) continue;
    for (size_t a = 0; a < mu; ++a)
      for (size_t b = 0; b < mu; ++b)
        if (a != b) o[u[a]][u[b]] += 1.0 / static_cast<double>(mu - 1);
  }
  std::map<std::string, double> nc;
  double n = 0, observed = 0;
  for (const auto& [c, row] : o)
    for (const auto& [k, v] : row) {
      nc[c] += v;
      n += v;
      if (c != k) observed += v;
    }
  double expected = 0;
  for (const auto& [c, a] : nc)
    for (const auto& [k, b] : nc)
      if (c != k) expected += a * b;
  if (n < 2 || expected == 0) return std::nullopt;
  return 1.0 - (n - 1) * observed / expected;
}

}  // namespace s4d::study
