// deform_reg: the HexPlane regularisers of ALGORITHMS.md 3.2 (spatial-plane smoothness, time-plane
// smoothness, L1 of the time planes to one), value and gradient. One invocation per plane float:
// it gathers its own gradient from the (up to three) second differences it enters, so v_planes is
// updated without atomics, and it contributes the second difference that starts at it (and its L1
// term) to the value. Each workgroup writes its value sum (a fixed-order tree) to partials.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "s4d_deform.h"
#include "flat_group.glsl"

layout(local_size_x = S4D_DEFORM_REG_WG) in;
layout(push_constant) uniform Push { DeformRegParams p; };
layout(std430, binding = S4D_B_DREG_PLANES) readonly buffer Planes { float planes[]; };
layout(std430, binding = S4D_B_DREG_V_PLANES) buffer VPlanes { float v_planes[]; };
layout(std430, binding = S4D_B_DREG_PARTIALS) writeonly buffer Partials { float partials[]; };

shared float s_sum[S4D_DEFORM_REG_WG];

// Second difference P[e + 2 row] - 2 P[e + row] + P[e] along the plane's height axis.
float second_difference(uint e, uint row) { return planes[e + 2u * row] - 2.0 * planes[e + row] + planes[e]; }

void main() {
  uint group = flat_group_id(), lid = gl_LocalInvocationIndex;
  if (group * S4D_DEFORM_REG_WG >= p.elements) return;  // whole workgroups only: barriers stay uniform
  uint e = group * S4D_DEFORM_REG_WG + lid;
  float value = 0.0;
  if (e < p.elements) {
    uint level = 0u, plane = 0u, offset = 0u;
    for (;;) {  // the (level, plane) holding e
      uint floats = deform_plane_floats(p.shape, level, plane);
      if (e < offset + floats) break;
      offset += floats;
      level += plane == uint(S4D_DEFORM_PLANES) - 1u ? 1u : 0u;
      plane = (plane + 1u) % uint(S4D_DEFORM_PLANES);
    }
    uint row = deform_axis_res(p.shape, level, S4D_DEFORM_PLANE_AXIS_U(plane)) * p.shape.channels;
    uint rv = deform_axis_res(p.shape, level, S4D_DEFORM_PLANE_AXIS_V(plane));
    uint v = (e - offset) / row;
    bool time_plane = S4D_DEFORM_PLANE_AXIS_V(plane) == S4D_DEFORM_TIME_AXIS;
    float w = (time_plane ? p.w_time_smoothness : p.w_plane_tv) / float((rv - 2u) * row);
    float grad = 0.0;
    if (v + 2u < rv) {  // the difference starting here: P[e] enters with +1
      float d = second_difference(e, row);
      value += w * d * d;
      grad += 2.0 * w * d;
    }
    if (v >= 1u && v + 1u < rv) grad -= 4.0 * w * second_difference(e - row, row);  // P[e] enters with -2
    if (v >= 2u) grad += 2.0 * w * second_difference(e - 2u * row, row);          // and with +1
    if (time_plane) {
      float l1 = p.w_l1_time / float(rv * row), r = 1.0 - planes[e];
      value += l1 * abs(r);
      grad -= l1 * sign(r);
    }
    v_planes[e] += grad;
  }
  s_sum[lid] = value;
  for (uint stride = uint(S4D_DEFORM_REG_WG) / 2u; stride > 0u; stride /= 2u) {
    barrier();
    if (lid < stride) s_sum[lid] += s_sum[lid + stride];
  }
  if (lid == 0u) partials[group] = s_sum[0];
}
