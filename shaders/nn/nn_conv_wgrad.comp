// nn_conv_wgrad: one chunk of rows' partial sums of a convolution's weight and bias gradients
// (s4d_nn_grad.h). S4D_NN_WGRAD_K = 3: ReflectionPad2d(1) + Conv2d(k=3), the taps read the reflected
// neighbours; 1: Conv2d(k=1). An invocation owns one input channel (or the bias, as a constant-1
// input at the centre tap) for a block of S4D_NN_WGRAD_COUT output channels and loops over its
// chunk's pixels (chunk_rows * (width + 1) <= S4D_NN_MAX_LOOP iterations, the host checks).
#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
#include "s4d_nn_grad.h"
#include "flat_group.glsl"

#define TAPS (S4D_NN_WGRAD_K * S4D_NN_WGRAD_K)
#define CENTRE (TAPS / 2)

layout(local_size_x = S4D_NN_WG) in;
layout(push_constant) uniform Push { NnWgradParams p; };
layout(std430, binding = S4D_B_WGRAD_X) readonly buffer X { float x[]; };
layout(std430, binding = S4D_B_WGRAD_DY) readonly buffer Dy { float dy[]; };
layout(std430, binding = S4D_B_WGRAD_PARTIAL) writeonly buffer Partial { float partial[]; };

uint reflect1(int i, uint n) { return uint(i < 0 ? -i : (i >= int(n) ? 2 * int(n) - 2 - i : i)); }

void main() {
  uint i = flat_group_id() * S4D_NN_WG + gl_LocalInvocationIndex;
  if (i >= p.invocations) return;
  uint blocks = (p.cout + S4D_NN_WGRAD_COUT - 1) / S4D_NN_WGRAD_COUT;
  uint ci = i % (p.cin + 1), rest = i / (p.cin + 1);
  uint co0 = (rest % blocks) * S4D_NN_WGRAD_COUT, chunk = rest / blocks;
  bool bias = ci == p.cin;
  uint src = bias ? 0u : ci;  // the bias reads channel 0 and weighs it 0 (below)
  float keep = bias ? 0.0 : 1.0, one = bias ? 1.0 : 0.0;
  uint co[S4D_NN_WGRAD_COUT];
  [[unroll]] for (uint j = 0; j < S4D_NN_WGRAD_COUT; ++j) co[j] = min(co0 + j, p.cout - 1);
  float acc[S4D_NN_WGRAD_COUT * TAPS];
  [[unroll]] for (uint k = 0; k < S4D_NN_WGRAD_COUT * TAPS; ++k) acc[k] = 0.0;
  uint plane = p.height * p.width, y0 = chunk * p.chunk_rows, y1 = min(y0 + p.chunk_rows, p.height);
  for (uint y = y0; y < y1; ++y) {
#if S4D_NN_WGRAD_K == 3
    uint rows[3];
    [[unroll]] for (int d = 0; d < 3; ++d) rows[d] = src * plane + reflect1(int(y) + d - 1, p.height) * p.width;
#endif
    for (uint xx = 0; xx < p.width; ++xx) {
      float v[TAPS];
#if S4D_NN_WGRAD_K == 3
      uint cols[3];
      [[unroll]] for (int d = 0; d < 3; ++d) cols[d] = reflect1(int(xx) + d - 1, p.width);
      [[unroll]] for (uint t = 0; t < 9; ++t) v[t] = keep * x[rows[t / 3] + cols[t % 3]];
#else
      v[0] = keep * x[src * plane + y * p.width + xx];
#endif
      v[CENTRE] += one;
      [[unroll]] for (uint j = 0; j < S4D_NN_WGRAD_COUT; ++j) {
        float g = dy[co[j] * plane + y * p.width + xx];
        [[unroll]] for (uint t = 0; t < TAPS; ++t) acc[j * TAPS + t] += g * v[t];
      }
    }
  }
  uint base = chunk * p.slots, weights = p.cout * p.cin * TAPS;
  [[unroll]] for (uint j = 0; j < S4D_NN_WGRAD_COUT; ++j) {
    if (co0 + j >= p.cout) continue;
    if (bias) {
      partial[base + weights + co0 + j] = acc[j * TAPS + CENTRE];
    } else {
      [[unroll]] for (uint t = 0; t < TAPS; ++t) partial[base + ((co0 + j) * p.cin + ci) * TAPS + t] = acc[j * TAPS + t];
    }
  }
}
