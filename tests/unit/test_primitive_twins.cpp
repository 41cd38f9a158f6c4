// The CPU twins of scan and radix sort against the standard library.
#include <doctest/doctest.h>

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <random>
#include <vector>

#include "s4d/ref/radix_sort_ref.h"
#include "s4d/ref/scan_ref.h"

TEST_CASE("scan twin matches std::exclusive_scan, wrapping modulo 2^32") {
  std::mt19937 rng(1);
  for (size_t n : {0u, 1u, 7u, 1000u}) {
    std::vector<uint32_t> v(n);
    for (auto& x : v) x = static_cast<uint32_t>(rng()) | 0x80000000u;  // large values force wrap-around
    std::vector<uint32_t> want(n);
    std::exclusive_scan(v.begin(), v.end(), want.begin(), uint32_t{0});
    s4d::ref::exclusive_scan(std::span(v));
    CHECK(v == want);
  }
  std::vector<uint64_t> w = {5, 0, 3};
  s4d::ref::exclusive_scan(std::span(w));
  CHECK(w == std::vector<uint64_t>{0, 5, 5});
}

TEST_CASE("radix sort twin equals a stable sort on the low key bits") {
  std::mt19937 rng(2);
  for (unsigned bits : {32u, 12u, 5u}) {
    std::vector<uint32_t> keys(5000), values(5000);
    for (size_t i = 0; i < keys.size(); ++i) {
      keys[i] = static_cast<uint32_t>(rng()) % 64 * 0x04000001u;  // few distinct low digits: many ties, stability matters
      values[i] = static_cast<uint32_t>(i);
    }
    const uint32_t mask = bits == 32 ? 0xffffffffu : (1u << bits) - 1;
    std::vector<uint32_t> order(keys.size());
    std::iota(order.begin(), order.end(), 0u);
    std::stable_sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return (keys[a] & mask) < (keys[b] & mask); });
    std::vector<uint32_t> want_keys(keys.size());
    for (size_t i = 0; i < order.size(); ++i) want_keys[i] = keys[order[i]];

    s4d::ref::radix_sort(keys, values, bits);
    CHECK(keys == want_keys);
    CHECK(values == order);
  }
}

TEST_CASE("radix sort twin handles all-bits-set, sorted and reversed keys") {
  std::vector<uint32_t> all(300, 0xffffffffu), sorted(300), reversed(300), idx(300);
  std::iota(sorted.begin(), sorted.end(), 0xfffff000u);
  std::iota(idx.begin(), idx.end(), 0u);
  reversed.assign(sorted.rbegin(), sorted.rend());
  auto v = idx;
  s4d::ref::radix_sort(all, v, 32);
  CHECK(v == idx);  // all keys equal: stable means order unchanged
  v = idx;
  auto s = sorted;
  s4d::ref::radix_sort(s, v, 32);
  CHECK(s == sorted);
  v = idx;
  auto r = reversed;
  s4d::ref::radix_sort(r, v, 32);
  CHECK(r == sorted);
  CHECK(v == std::vector<uint32_t>(idx.rbegin(), idx.rend()));
}
