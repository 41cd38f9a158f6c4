// CPU twin of the GPU radix sort (engine/primitives/radix_sort.cpp): the same LSD passes of
// `digit_bits` bits over the low `key_bits` bits (the last digit narrower when key_bits is not a
// multiple), each a stable counting sort. Keys are any unsigned integer type.
#pragma once
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <vector>

namespace s4d::ref {

// Twin of radix_count: digit histogram of each block of `block` keys, digit-major
// (hist[d * num_blocks + b]) like the GPU's.
template <class Key>
std::vector<uint32_t> radix_block_histograms(const std::vector<Key>& keys, unsigned shift, Key digit_mask,
                                             size_t block, size_t bins) {
  const size_t num_blocks = (keys.size() + block - 1) / block;
  std::vector<uint32_t> hist(bins * num_blocks, 0);
  for (size_t i = 0; i < keys.size(); ++i) ++hist[((keys[i] >> shift) & digit_mask) * num_blocks + i / block];
  return hist;
}

// Twin of one radix_scatter pass (with its count and scan): a stable counting sort on one digit.
template <class Key, class Value>
void radix_sort_pass(std::vector<Key>& keys, std::vector<Value>& values, unsigned shift, unsigned digit_bits) {
  const size_t bins = size_t{1} << digit_bits;
  const Key mask = static_cast<Key>(bins - 1);
  std::vector<size_t> offset(bins + 1, 0);
  for (const Key k : keys) ++offset[((k >> shift) & mask) + 1];
  for (size_t b = 1; b <= bins; ++b) offset[b] += offset[b - 1];
  std::vector<Key> out_k(keys.size());
  std::vector<Value> out_v(values.size());
  for (size_t i = 0; i < keys.size(); ++i) {
    const size_t d = (keys[i] >> shift) & mask;
    out_k[offset[d]] = keys[i];
    out_v[offset[d]] = values[i];
    ++offset[d];
  }
  keys.swap(out_k);
  values.swap(out_v);
}

template <class Key, class Value>
void radix_sort(std::vector<Key>& keys, std::vector<Value>& values, unsigned key_bits, unsigned digit_bits = 4) {
  if (keys.size() != values.size()) throw std::invalid_argument("radix_sort: keys and values differ in length");
  if (key_bits == 0 || key_bits > 8 * sizeof(Key)) throw std::invalid_argument("radix_sort: key_bits out of range");
  for (unsigned shift = 0; shift < key_bits; shift += digit_bits)
    radix_sort_pass(keys, values, shift, std::min(digit_bits, key_bits - shift));
}

}  // namespace s4d::ref
