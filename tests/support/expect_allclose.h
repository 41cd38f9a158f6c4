// Elementwise float comparison in gsplat's form: |actual - expected| <= atol + rtol * |expected|
// (atol optionally widened by a fraction of the largest |expected|).
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
  // A fraction of the largest |expected|, added to atol: one scale for a whole array, for results
  // whose small entries are float sums of large terms (reordered sums cannot give them relative accuracy).
  double of_largest = 0;
};

struct AllcloseReport {
  bool ok = true;
  std::string message;  // empty when ok
};

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
  double largest = 0;
  for (const E& x : expected)
    if (std::isfinite(static_cast<double>(x))) largest = std::max(largest, std::abs(static_cast<double>(x)));
  const double atol = tol.atol + tol.of_largest * largest;
  size_t bad = 0, worst = 0;
  double worst_ratio = 0;
  std::ostringstream first;
  first.precision(9);
  for (size_t i = 0; i < actual.size(); ++i) {
    const double a = static_cast<double>(actual[i]), e = static_cast<double>(expected[i]);
    if (!std::isfinite(e)) continue;  // matched exactly above
    const double diff = std::abs(a - e), allowed = atol + tol.rtol * std::abs(e);
    const double ratio = allowed > 0 ? diff / allowed : (diff > 0 ? HUGE_VAL : 0);
    if (ratio > worst_ratio) worst_ratio = ratio, worst = i;
    if (diff <= allowed) continue;
    if (bad < 5) first << "\n  [" << i << "] " << a << " vs " << e;
    ++bad;
  }
  if (bad == 0) return {};
  const double a = static_cast<double>(actual[worst]), e = static_cast<double>(expected[worst]);
  out << what << ": " << bad << " of " << actual.size() << " elements outside atol " << tol.atol;
  if (tol.of_largest > 0) out << " + " << tol.of_largest << " * largest |expected| " << largest;
  out << " + rtol " << tol.rtol << " * |expected|; worst [" << worst << "] " << a << " vs " << e << " (|diff| "
      << std::abs(a - e) << " > " << atol + tol.rtol * std::abs(e) << ")" << first.str();
  return {false, out.str()};
}

template <class A, class E>
void expect_allclose(const std::vector<A>& actual, const std::vector<E>& expected, Tolerance tol,
                     const std::string& what) {
  const AllcloseReport r = allclose_report(actual, expected, tol, what);
  CHECK_MESSAGE(r.ok, r.message);
}

}  // namespace s4d::test
