// grad_mask: values[i] = 0 where the mask of row i / row is 0; keeps the gradients (and so the
// parameters, whose Adam moments then stay zero) of Gaussians outside a stylized region unchanged.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "s4d_optim.h"
#include "flat_group.glsl"

layout(local_size_x = S4D_MASK_WG) in;
layout(push_constant) uniform Push { MaskParams p; };
layout(std430, binding = S4D_B_MASK_VALUES) buffer Values { float values[]; };
layout(std430, binding = S4D_B_MASK_ROWS) readonly buffer Rows { uint rows[]; };

void main() {
  uint i = flat_group_id() * S4D_MASK_WG + gl_LocalInvocationIndex;
  if (i < p.n && rows[i / p.row] == 0u) values[i] = 0.0;
}
