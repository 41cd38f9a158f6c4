// Half storage: float arrays held as IEEE binary16 values packed two to a 32-bit word, element j in
// word j / 2 (low half for even j, high for odd), read with unpackHalf2x16 (core GLSL 4.20, so no
// 16-bit storage feature is needed). The host packs them with io::pack_halves (s4d/io/half_float.h).
// unpackHalf2x16 gives the half's exact value as a float, so a kernel reading halves computes what
// its float variant computes on the rounded values.
#ifndef HALF_STORAGE_GLSL
#define HALF_STORAGE_GLSL

// Element j of a packed array whose word j / 2 is `word`.
float half_element(uint word, uint j) {
  vec2 pair = unpackHalf2x16(word);
  return (j & 1u) == 0u ? pair.x : pair.y;
}

// Four consecutive elements 4 v .. 4 v + 3 from their two words (a vec4 of a float array).
vec4 half_vec4(uvec2 words) { return vec4(unpackHalf2x16(words.x), unpackHalf2x16(words.y)); }

#endif  // HALF_STORAGE_GLSL
