// Exact comparison of integer arrays with a useful report: how many differ, the first few with
// their indices and values (integers only; floats go through tolerance helpers).
#pragma once
#include <doctest/doctest.h>

#include <cstddef>
#include <sstream>
#include <string>
#include <vector>

namespace s4d::test {

template <class T>
void expect_equal_arrays(const std::vector<T>& actual, const std::vector<T>& expected, const std::string& what) {
  REQUIRE_MESSAGE(actual.size() == expected.size(), what << ": sizes differ");
  size_t bad = 0;
  std::ostringstream first;
  for (size_t i = 0; i < actual.size(); ++i) {
    if (actual[i] == expected[i]) continue;
    if (bad < 5) first << "\n  [" << i << "] got " << actual[i] << " want " << expected[i];
    ++bad;
  }
  CHECK_MESSAGE(bad == 0, what << ": " << bad << " of " << actual.size() << " elements differ" << first.str());
}

}  // namespace s4d::test
