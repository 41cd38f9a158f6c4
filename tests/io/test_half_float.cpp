// IEEE binary16 conversions and the packing of the render side's half storage (s4d/io/half_float.h):
// round to nearest even, infinities, NaN, subnormals, overflow, and the two-halves-a-word layout
// that unpackHalf2x16 reads.
#include <doctest/doctest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "s4d/io/half_float.h"

using s4d::io::float_to_half;
using s4d::io::half_to_float;

TEST_CASE("every finite half converts to float and back to the same bits") {
  for (uint32_t h = 0; h < 0x10000u; ++h) {
    if ((h & 0x7c00u) == 0x7c00u && (h & 0x3ffu) != 0) continue;  // NaNs: next case
    CAPTURE(h);
    CHECK(float_to_half(half_to_float(static_cast<uint16_t>(h))) == h);
  }
}

TEST_CASE("float to half rounds to nearest, ties to even") {
  const float ulp = std::ldexp(1.0f, -10);  // half's spacing in [1, 2)
  CHECK(float_to_half(1.0f + ulp / 2) == 0x3c00u);                        // tie: down to the even 1
  CHECK(float_to_half(1.0f + 3 * ulp / 2) == 0x3c02u);                    // tie: up to the even 1 + 2 ulp
  CHECK(float_to_half(1.0f + ulp / 2 + std::ldexp(1.0f, -20)) == 0x3c01u);  // past the tie: up
  CHECK(float_to_half(1.0f + ulp / 2 - std::ldexp(1.0f, -20)) == 0x3c00u);  // below the tie: down
  CHECK(float_to_half(2.0f - ulp / 4) == 0x4000u);                        // a carry into the exponent
  CHECK(float_to_half(-1.0f - 3 * ulp / 2) == 0xbc02u);                   // signs round symmetrically
}

TEST_CASE("float to half keeps infinities, NaN and signed zero") {
  CHECK(float_to_half(std::numeric_limits<float>::infinity()) == 0x7c00u);
  CHECK(float_to_half(-std::numeric_limits<float>::infinity()) == 0xfc00u);
  const uint16_t nan = float_to_half(std::numeric_limits<float>::quiet_NaN());
  CHECK((nan & 0x7c00u) == 0x7c00u);
  CHECK((nan & 0x3ffu) != 0);
  CHECK(std::isnan(half_to_float(nan)));
  CHECK(std::isnan(half_to_float(float_to_half(std::bit_cast<float>(0x7f800001u)))));  // a signalling NaN too
  CHECK(float_to_half(0.0f) == 0x0000u);
  CHECK(float_to_half(-0.0f) == 0x8000u);
}

TEST_CASE("float to half gives subnormals below 2^-14, rounding to nearest even, and zero below 2^-25") {
  const float tiny = std::ldexp(1.0f, -24);  // the smallest subnormal half
  CHECK(float_to_half(tiny) == 0x0001u);
  CHECK(half_to_float(0x0001u) == tiny);
  CHECK(float_to_half(tiny / 2) == 0x0000u);          // tie between 0 and the smallest: the even 0
  CHECK(float_to_half(tiny * 0.75f) == 0x0001u);      // past the tie
  CHECK(float_to_half(tiny * 2.5f) == 0x0002u);       // tie between 2 and 3 subnormal steps: 2
  CHECK(float_to_half(tiny * 3.5f) == 0x0004u);       // tie between 3 and 4: 4
  CHECK(float_to_half(std::ldexp(1.0f, -14)) == 0x0400u);  // the smallest normal
  CHECK(float_to_half(std::ldexp(1.0f, -14) - tiny) == 0x03ffu);  // the largest subnormal
  CHECK(float_to_half(-tiny) == 0x8001u);
  CHECK(float_to_half(1e-30f) == 0x0000u);
}

TEST_CASE("float to half overflows to infinity from 65520 up; 65504 is the largest half") {
  CHECK(float_to_half(65504.0f) == 0x7bffu);
  CHECK(float_to_half(65519.0f) == 0x7bffu);  // below the tie with 65536: down
  CHECK(float_to_half(65520.0f) == 0x7c00u);  // the tie rounds to the even, 65536: beyond range, infinity
  CHECK(float_to_half(1e6f) == 0x7c00u);
  CHECK(float_to_half(-7e4f) == 0xfc00u);
  CHECK(float_to_half(std::numeric_limits<float>::max()) == 0x7c00u);
}

TEST_CASE("pack_halves puts element j in word j / 2, even j in the low half, and unpack_halves reads it back") {
  const std::vector<uint32_t> words = s4d::io::pack_halves(std::vector<float>{1.0f, 2.0f, -3.0f});
  REQUIRE(words.size() == 2);
  CHECK(words[0] == 0x40003c00u);  // 2.0 high, 1.0 low
  CHECK(words[1] == 0x0000c200u);  // -3.0 low; the odd count's last high half is zero
  CHECK(s4d::io::unpack_halves(words, 3) == std::vector<float>{1.0f, 2.0f, -3.0f});
  CHECK(s4d::io::pack_halves(std::vector<float>{}).empty());
  const std::vector<float> values = {0.1f, -0.3333f, 1e-6f, 1234.5f, 65504.0f};
  const std::vector<float> back = s4d::io::unpack_halves(s4d::io::pack_halves(values), values.size());
  for (size_t j = 0; j < values.size(); ++j) CHECK(back[j] == half_to_float(float_to_half(values[j])));
}
