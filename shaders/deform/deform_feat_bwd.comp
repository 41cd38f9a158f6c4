// deform_feat_bwd: backward of deform_feat for the Gaussians p.first .. p.n - 1 of the moving
// prefix, one invocation per Gaussian, from dL/d features in its scratch row (deform_bwd wrote
// them): each plane sample's cotangent (dL/d feature times the level's other five samples) is
// scattered to its 4 texels with atomic adds, and the field's term of dL/d canonical mean (through
// the grid coordinates; time carries none) is added in place to v_means, which holds dL/d deformed
// mean on entry. The other raw parameters' gradients pass through unchanged (deformed = canonical +
// delta); still Gaussians follow the prefix and are never visited. There are no barriers: every
// invocation may return early.
// S4D_FLOAT_ATOMICS=1 adds with float atomics; 0 with compare-and-swap loops.
// Specialization constant S4D_DEFORM_SPEC_CHANNELS sizes the private samples (capacity only, never results).
#version 450
#extension GL_GOOGLE_include_directive : require
#if S4D_FLOAT_ATOMICS
#extension GL_EXT_shader_atomic_float : require
#endif
#include "s4d_deform.h"
#include "flat_group.glsl"

layout(local_size_x = S4D_DEFORM_WG) in;
layout(push_constant) uniform Push { DeformParams p; };
layout(std430, binding = S4D_B_DFB_PLANES) readonly buffer Planes { float planes[]; };
layout(std430, binding = S4D_B_DFB_MEANS) readonly buffer Means { float means[]; };      // [N, 3]
layout(std430, binding = S4D_B_DFB_V_MEANS) buffer VMeans { float v_means[]; };          // [N, 3] in/out
layout(std430, binding = S4D_B_DFB_SCRATCH) readonly buffer Scratch { float scratch[]; };  // [rows, row floats]
#if S4D_FLOAT_ATOMICS
layout(std430, binding = S4D_B_DFB_V_PLANES) buffer VPlanes { float v_planes[]; };
void add_v_planes(uint k, float value) { atomicAdd(v_planes[k], value); }
#else
layout(std430, binding = S4D_B_DFB_V_PLANES) buffer VPlanes { uint v_planes[]; };
// Compare-and-swap adds; the first read is atomic, as a plain load would race the swaps.
void add_v_planes(uint k, float value) {
  uint old = atomicOr(v_planes[k], 0u);
  for (;;) {
    uint seen = atomicCompSwap(v_planes[k], old, floatBitsToUint(uintBitsToFloat(old) + value));
    if (seen == old) break;
    old = seen;
  }
}
#endif

#include "deform_field.glsl"

layout(constant_id = S4D_DEFORM_SPEC_CHANNELS) const uint CHANNELS_CAP = S4D_DEFORM_MAX_CHANNELS;
float g_samples[S4D_DEFORM_PLANES * CHANNELS_CAP];

void main() {
  uint row = flat_group_id() * S4D_DEFORM_WG + gl_LocalInvocationIndex, i = p.first + row;
  if (i >= p.n) return;
  vec4 g = deform_coords(vec3(means[3u * i], means[3u * i + 1u], means[3u * i + 2u]));
  uint C = p.shape.channels, offset = 0u, v_feat = row * deform_scratch_floats(p.shape) + deform_v_feat_col(p.shape);
  vec3 v_xyz = vec3(0.0);
  for (uint l = 0u; l < p.shape.levels; ++l) {
    DeformTap taps[S4D_DEFORM_PLANES];
    deform_level_taps(l, g, offset, taps);
    for (uint plane = 0u; plane < uint(S4D_DEFORM_PLANES); ++plane)
      for (uint c = 0u; c < C; ++c) g_samples[plane * C + c] = tap_value(taps[plane], c);
    for (uint plane = 0u; plane < uint(S4D_DEFORM_PLANES); ++plane) {
      DeformTap t = taps[plane];
      float v_ix = 0.0, v_iy = 0.0;
      for (uint c = 0u; c < C; ++c) {
        float others = scratch[v_feat + l * C + c];  // dL/d sample: v_feat times the other five samples
        for (uint q = 0u; q < uint(S4D_DEFORM_PLANES); ++q)
          if (q != plane) others *= g_samples[q * C + c];
        uint k = t.base + c;
        add_v_planes(k, (1.0 - t.wx) * (1.0 - t.wy) * others);
        add_v_planes(k + t.step_x, t.wx * (1.0 - t.wy) * others);
        add_v_planes(k + t.step_y, (1.0 - t.wx) * t.wy * others);
        add_v_planes(k + t.step_y + t.step_x, t.wx * t.wy * others);
        float v00 = planes[k], v10 = planes[k + t.step_x], v01 = planes[k + t.step_y];
        float v11 = planes[k + t.step_y + t.step_x];
        v_ix += others * ((1.0 - t.wy) * (v10 - v00) + t.wy * (v11 - v01));
        v_iy += others * ((1.0 - t.wx) * (v01 - v00) + t.wx * (v11 - v10));
      }
      uint au = S4D_DEFORM_PLANE_AXIS_U(plane), av = S4D_DEFORM_PLANE_AXIS_V(plane);
      if (au < 3u) v_xyz[au] += v_ix * t.dix * p.aabb_scale[au];  // time carries no gradient
      if (av < 3u) v_xyz[av] += v_iy * t.diy * p.aabb_scale[av];
    }
  }
  for (uint k = 0u; k < 3u; ++k) v_means[3u * i + k] += v_xyz[k];
}
