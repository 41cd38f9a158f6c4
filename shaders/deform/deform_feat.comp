// deform_feat: the HexPlane features of the Gaussians p.first .. p.n - 1 of the moving prefix
// (ALGORITHMS.md 3.1; mapping and layouts in s4d_deform.h), one invocation per Gaussian: per level,
// the product of its 6 planes' bilinear samples (in plane order, from 1), levels concatenated, to
// the feat columns of the Gaussian's scratch row for deform_fwd.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "s4d_deform.h"
#include "flat_group.glsl"

layout(local_size_x = S4D_DEFORM_WG) in;
layout(push_constant) uniform Push { DeformParams p; };
layout(std430, binding = S4D_B_DFEAT_PLANES) readonly buffer Planes { float planes[]; };
layout(std430, binding = S4D_B_DFEAT_MEANS) readonly buffer Means { float means[]; };   // [N, 3]
layout(std430, binding = S4D_B_DFEAT_SCRATCH) writeonly buffer Scratch { float scratch[]; };  // [rows, row floats]

#include "deform_field.glsl"

void main() {
  uint row = flat_group_id() * S4D_DEFORM_WG + gl_LocalInvocationIndex, i = p.first + row;
  if (i >= p.n) return;
  vec4 g = deform_coords(vec3(means[3u * i], means[3u * i + 1u], means[3u * i + 2u]));
  uint C = p.shape.channels, offset = 0u, at = row * deform_scratch_floats(p.shape);
  for (uint l = 0u; l < p.shape.levels; ++l) {
    DeformTap taps[S4D_DEFORM_PLANES];
    deform_level_taps(l, g, offset, taps);
    for (uint c = 0u; c < C; ++c) {
      float f = 1.0;
      for (uint plane = 0u; plane < uint(S4D_DEFORM_PLANES); ++plane) f *= tap_value(taps[plane], c);
      scratch[at + l * C + c] = f;
    }
  }
}
