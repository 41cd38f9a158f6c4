// IEEE binary16 and bfloat16 to and from float, bit-exact: the safetensors reader and writer, and
// the render side's half storage of SH and style MLPs (packed two to a 32-bit word, as the kernels
// read them with unpackHalf2x16: shaders/include/half_storage.glsl).
#pragma once
#include <bit>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace s4d::io {

inline float half_to_float(uint16_t h) {
  const uint32_t sign = uint32_t{h & 0x8000u} << 16;
  const uint32_t exponent = (h >> 10) & 0x1fu;
  uint32_t mantissa = h & 0x3ffu;
  if (exponent == 0x1f) return std::bit_cast<float>(sign | 0x7f800000u | (mantissa << 13));  // inf, NaN
  if (exponent != 0) return std::bit_cast<float>(sign | ((exponent + 112) << 23) | (mantissa << 13));
  if (mantissa == 0) return std::bit_cast<float>(sign);
  // Subnormal half: renormalise into a float exponent.
  int e = 113;
  while ((mantissa & 0x400u) == 0) {
    mantissa <<= 1;
    --e;
  }
  return std::bit_cast<float>(sign | (static_cast<uint32_t>(e) << 23) | ((mantissa & 0x3ffu) << 13));
}

// Round to nearest even; overflow (|f| >= 65520, which rounds past the largest half, 65504) gives
// infinity, tiny values subnormals or zero; NaN stays a (quiet) NaN with its sign.
inline uint16_t float_to_half(float f) {
  const uint32_t x = std::bit_cast<uint32_t>(f);
  const uint16_t sign = static_cast<uint16_t>((x >> 16) & 0x8000u);
  const uint32_t abs = x & 0x7fffffffu;
  if (abs >= 0x7f800000u) return static_cast<uint16_t>(sign | 0x7c00u | (abs > 0x7f800000u ? 0x200u : 0u));
  if (abs >= 0x477ff000u) return static_cast<uint16_t>(sign | 0x7c00u);  // rounds past 65504
  // Below the smallest normal half (2^-14): subnormal or zero.
  if (abs < 0x38800000u) {
    if (abs < 0x33000000u) return sign;  // below half of the smallest subnormal (2^-25)
    const uint32_t mantissa = (abs & 0x7fffffu) | 0x800000u;
    const uint32_t shift = 126 - (abs >> 23);  // 14..24
    uint32_t h = mantissa >> shift;
    const uint32_t rest = mantissa & ((1u << shift) - 1), halfway = 1u << (shift - 1);
    if (rest > halfway || (rest == halfway && (h & 1u))) ++h;
    return static_cast<uint16_t>(sign | h);
  }
  uint32_t h = ((abs >> 23) - 112) << 10 | ((abs >> 13) & 0x3ffu);
  const uint32_t rest = abs & 0x1fffu;
  if (rest > 0x1000u || (rest == 0x1000u && (h & 1u))) ++h;  // a carry into the exponent is correct
  return static_cast<uint16_t>(sign | h);
}

inline float bf16_to_float(uint16_t b) { return std::bit_cast<float>(uint32_t{b} << 16); }

inline uint16_t float_to_bf16(float f) {
  const uint32_t x = std::bit_cast<uint32_t>(f);
  if ((x & 0x7fffffffu) > 0x7f800000u) return static_cast<uint16_t>((x >> 16) | 0x40u);  // keep NaN a NaN
  return static_cast<uint16_t>((x + 0x7fffu + ((x >> 16) & 1u)) >> 16);
}

// `values` rounded to halves (float_to_half) and packed two to a 32-bit word: element j in word
// j / 2, the low 16 bits for even j and the high 16 for odd j; an odd count's last high half is 0.
inline std::vector<uint32_t> pack_halves(std::span<const float> values) {
  std::vector<uint32_t> words((values.size() + 1) / 2, 0u);
  for (size_t j = 0; j < values.size(); ++j) words[j / 2] |= uint32_t{float_to_half(values[j])} << (16 * (j % 2));
  return words;
}

// The first `count` elements of pack_halves' layout as floats.
inline std::vector<float> unpack_halves(std::span<const uint32_t> words, size_t count) {
  std::vector<float> out(count);
  for (size_t j = 0; j < count; ++j) out[j] = half_to_float(static_cast<uint16_t>(words[j / 2] >> (16 * (j % 2))));
  return out;
}

}  // namespace s4d::io
