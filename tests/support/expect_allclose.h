// Elementwise float comparison in gsplat's form: |actual - expected| <= atol + rtol * |expected|.
// Non-finite values are checked first: a NaN or infinity where a finite value is expected fails and
// names its index, and a non-finite expected value must be matched exactly (the same infinity, or
// NaN). The report names the tolerance, how many elements fail, the worst one (by how far past its
// tolerance) with both values, and the first few failures.
#pragma once
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <sstream>
#include <string>
#include <vector>

namespace s4d::test {

struct Tolerance {
  double atol = 0;
  double rtol = 0;
};

struct AllcloseReport {
  bool ok = true;
  std::string message;  // empty when ok
};

// The largest |x| of an array: the scale for a tolerance relative to the whole array.
template <class T>
double max_magnitude(const std::vector<T>& v) {
  double m = 0;
  for (const T& x : v)
    if (std::isfinite(static_cast<double>(x))) m = std::max(m, std::abs(static_cast<double>(x)));
  return m;
}

template <class A, class E>
AllcloseReport allclose_report(const std::vector<A>& actual, const std::vector<E>& expected, Tolerance tol,
                               const std::string& what) {
  std::ostringstream out;
  out.precision(9);
  if (actual.size() != expected.size()) {
    out << what << ": " << actual.size() << " elements, expected " << expected.size();
    return {false, out.str()};
  }
  // Non-finite first: the distance test below would read NaN as "not greater" and pass it.
  for (size_t i = 0; i < actual.size(); ++i) {
    const double a = static_cast<double>(actual[i]), e = static_cast<double>(expected[i]);
    const bool same_non_finite = std::isnan(e) ? std::isnan(a) : (std::isinf(e) && a == e);
    if (std::isfinite(e) ? std::isfinite(a) : same_non_finite) continue;
    out << what << ": [" << i << "] is " << a << ", expected " << e;
    return {false, out.str()};
  }
  size_t bad = 0, worst = 0;
  double worst_ratio = 0;
  std::ostringstream first;
  first.precision(9);
  for (size_t i = 0; i < actual.size(); ++i) {
    const double a = static_cast<double>(actual[i]), e = static_cast<double>(expected[i]);
    if (!std::isfinite(e)) continue;  // matched exactly above
    const double diff = std::abs(a - e), allowed = tol.atol + tol.rtol * std::abs(e);
    const double ratio = allowed > 0 ? diff / allowed : (diff > 0 ? HUGE_VAL : 0);
    if (ratio > worst_ratio) worst_ratio = ratio, worst = i;
    if (diff <= allowed) continue;
    if (bad < 5) first << "\n  [" << i << "] " << a << " vs " << e;
    ++bad;
  }
  if (bad == 0) return {};
  const double a = static_cast<double>(actual[worst]), e = static_cast<double>(expected[worst]);
  out << what << ": " << bad << " of " << actual.size() << " elements outside atol " << tol.atol << " + rtol "
      << tol.rtol << " * |expected|; worst [" << worst << "] " << a << " vs " << e << " (|diff| " << std::abs(a - e)
      << " > " << tol.atol + tol.rtol * std::abs(e) << ")" << first.str();
  return {false, out.str()};
}

template <class A, class E>
void expect_allclose(const std::vector<A>& actual, const std::vector<E>& expected, Tolerance tol,
                     const std::string& what) {
  const AllcloseReport r = allclose_report(actual, expected, tol, what);
  CHECK_MESSAGE(r.ok, r.message);
}

}  // namespace s4d::test
