// nn_transpose: out[c, r] = in[r, c] for a [rows, cols] matrix (s4d_nn.h; NnEltParams: n = rows * cols,
// count = cols), one invocation per output value. The transformer's attention uses it to turn the
// queries and the attention weights into the layouts nn_conv1x1 multiplies (attention.h).
#version 450
#extension GL_GOOGLE_include_directive : require
#include "s4d_nn.h"
#include "flat_group.glsl"

layout(local_size_x = S4D_NN_WG) in;
layout(push_constant) uniform Push { NnEltParams p; };
layout(std430, binding = S4D_B_TRANSPOSE_IN) readonly buffer In { float x[]; };
layout(std430, binding = S4D_B_TRANSPOSE_OUT) writeonly buffer Out { float y[]; };

void main() {
  uint i = flat_group_id() * S4D_NN_WG + gl_LocalInvocationIndex;
  if (i >= p.n) return;
  uint rows = p.n / p.count, c = i / rows, r = i % rows;
  y[i] = x[r * p.count + c];
}
