// Dual-language preamble: valid C++17 and GLSL 450. Include it first in every shared header.
//
// Rules for shared blocks (checked by tests/unit/test_shared_layouts.cpp against the SPIR-V):
//  - members are 4-byte scalars (uint, int, float) or 16-byte vec4/uvec4/ivec4; never vec3 (its
//    std430 array stride is 16, not 12);
//  - every struct is padded explicitly to a multiple of 16 bytes, so sizeof equals the std430 size.
#ifndef S4D_COMMON_H
#define S4D_COMMON_H

#ifdef __cplusplus
#include <cstdint>
#define S4D_CONSTANT inline constexpr
#define S4D_NAMESPACE_BEGIN namespace s4d::gpu {
#define S4D_NAMESPACE_END }
namespace s4d::gpu {
using uint = uint32_t;
struct alignas(16) vec4 { float x, y, z, w; };
struct alignas(16) uvec4 { uint32_t x, y, z, w; };
struct alignas(16) ivec4 { int32_t x, y, z, w; };
}  // namespace s4d::gpu
#else
#define S4D_CONSTANT const
#define S4D_NAMESPACE_BEGIN
#define S4D_NAMESPACE_END
#endif

// Push constants: 128 bytes is both the Vulkan minimum guarantee and lavapipe's limit.
#define S4D_MAX_PUSH_CONSTANT_BYTES 128

#endif  // S4D_COMMON_H
