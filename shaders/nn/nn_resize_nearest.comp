// nn_resize_nearest: nearest-neighbour resize to any size, PyTorch's interpolate(size=(h, w)) default
// mode: source index floor(dst * in / out), here in integers (PyTorch computes the scale in float,
// which can pick the neighbour for a few sizes; for out = 2 in and in = k out both agree exactly).
#version 450
#extension GL_GOOGLE_include_directive : require
#include "s4d_nn.h"
#include "flat_group.glsl"

layout(local_size_x = S4D_NN_WG) in;
layout(push_constant) uniform Push { NnResizeParams p; };
layout(std430, binding = S4D_B_RESIZE_IN) readonly buffer In { float x[]; };
layout(std430, binding = S4D_B_RESIZE_OUT) writeonly buffer Out { float y[]; };

void main() {
  uint i = flat_group_id() * S4D_NN_WG + gl_LocalInvocationIndex;
  if (i >= p.n_out) return;
  uint ox = i % p.out_width, oy = (i / p.out_width) % p.out_height, c = i / (p.out_width * p.out_height);
  // The host keeps out * in below 2^32.
  uint sy = oy * p.in_height / p.out_height, sx = ox * p.in_width / p.out_width;
  y[i] = x[(c * p.in_height + sy) * p.in_width + sx];
}
