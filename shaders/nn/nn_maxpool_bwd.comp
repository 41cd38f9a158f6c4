// nn_maxpool_bwd: the adjoint of nn_maxpool (2x2, stride 2, ceil mode): each input element gets its
// window's dy when it is the window's first maximum in row-major order (PyTorch's rule, which
// matters for ReLU zeros), else 0 (s4d_nn_grad.h). One invocation per input element.
#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
#include "s4d_nn_grad.h"
#include "flat_group.glsl"

layout(local_size_x = S4D_NN_WG) in;
layout(push_constant) uniform Push { NnResizeParams p; };
layout(std430, binding = S4D_B_POOLB_X) readonly buffer X { float x[]; };
layout(std430, binding = S4D_B_POOLB_DY) readonly buffer Dy { float dy[]; };
layout(std430, binding = S4D_B_POOLB_DX) writeonly buffer Dx { float dx[]; };

void main() {
  uint i = flat_group_id() * S4D_NN_WG + gl_LocalInvocationIndex;
  if (i >= p.n_out) return;
  uint px = i % p.in_width, py = (i / p.in_width) % p.in_height, c = i / (p.in_width * p.in_height);
  uint ox = px / 2, oy = py / 2, base = c * p.in_height * p.in_width;
  // The window in row-major order; a window over the last row or column repeats its covered values,
  // which a strict comparison never prefers.
  uint xs[2] = uint[2](2 * ox, min(2 * ox + 1, p.in_width - 1));
  uint ys[2] = uint[2](2 * oy, min(2 * oy + 1, p.in_height - 1));
  float best = x[base + ys[0] * p.in_width + xs[0]];
  uint arg = ys[0] * p.in_width + xs[0];
  [[unroll]] for (uint k = 1; k < 4; ++k) {
    uint at = ys[k / 2] * p.in_width + xs[k % 2];
    float v = x[base + at];
    if (v > best) {
      best = v;
      arg = at;
    }
  }
  dx[i] = arg == py * p.in_width + px ? dy[(c * p.out_height + oy) * p.out_width + ox] : 0.0;
}
