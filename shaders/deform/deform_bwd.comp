// deform_bwd: backward of deform_fwd. One invocation per Gaussian recomputes its features and MLP
// activations (nothing is saved by the forward), then walks the layers back to front:
//  - MLP weight and bias gradients: each Linear layer's input (after its ReLU) and output cotangent
//    go to this Gaussian's scratch row (layout: deform_scratch_col in s4d_deform.h); deform_wgrad
//    sums them over Gaussians afterwards;
//  - plane gradients: each sample's cotangent is scattered to its 4 texels with atomic adds;
//  - dL/d canonical mean: the field's term (through the grid coordinates) is added in place to
//    v_means, which holds dL/d deformed mean on entry. The other raw parameters' gradients pass
//    through unchanged (deformed = canonical + delta), so their buffers are only read.
// One pass covers Gaussians p.first .. p.n - 1 (scratch rows 0 ..) of the moving prefix; static
// Gaussians follow it and are never visited (their cotangents pass through unchanged). There are no
// barriers: every invocation may return early.
// S4D_FLOAT_ATOMICS=1 adds with float atomics; 0 with compare-and-swap loops.
// Specialization constants S4D_DEFORM_SPEC_* size the private arrays (capacity only, never results).
#version 450
#extension GL_GOOGLE_include_directive : require
#if S4D_FLOAT_ATOMICS
#extension GL_EXT_shader_atomic_float : require
#endif
#include "s4d_deform.h"
#include "flat_group.glsl"

layout(local_size_x = S4D_DEFORM_WG) in;
layout(push_constant) uniform Push { DeformParams p; };
layout(std430, binding = S4D_B_DBWD_PLANES) readonly buffer Planes { float planes[]; };
layout(std430, binding = S4D_B_DBWD_MLP) readonly buffer Mlp { float mlp[]; };
layout(std430, binding = S4D_B_DBWD_MEANS) readonly buffer Means { float means[]; };              // [N, 3]
layout(std430, binding = S4D_B_DBWD_V_MEANS) buffer VMeans { float v_means[]; };                  // [N, 3] in/out
layout(std430, binding = S4D_B_DBWD_V_LOG_SCALES) readonly buffer VLogScales { float v_log_scales[]; };
layout(std430, binding = S4D_B_DBWD_V_QUATS) readonly buffer VQuats { float v_quats[]; };
layout(std430, binding = S4D_B_DBWD_V_OPACITY_LOGITS) readonly buffer VOpacity { float v_opacity[]; };
layout(std430, binding = S4D_B_DBWD_V_SH) readonly buffer VSh { float v_sh[]; };
layout(std430, binding = S4D_B_DBWD_SCRATCH) writeonly buffer Scratch { float scratch[]; };    // [rows, row floats]
#if S4D_FLOAT_ATOMICS
layout(std430, binding = S4D_B_DBWD_V_PLANES) buffer VPlanes { float v_planes[]; };
void add_v_planes(uint k, float value) { atomicAdd(v_planes[k], value); }
#else
layout(std430, binding = S4D_B_DBWD_V_PLANES) buffer VPlanes { uint v_planes[]; };
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

#include "deform_mlp.glsl"
#include "deform_field.glsl"

float g_v[ACT_SIZE];  // cotangents, same segments as g_act (of the pre-activations)
layout(constant_id = S4D_DEFORM_SPEC_CHANNELS) const uint CHANNELS_CAP = S4D_DEFORM_MAX_CHANNELS;
float g_samples[S4D_DEFORM_PLANES * CHANNELS_CAP];

// Layer l's input g_act[in_at ..] (through ReLU if relu_in) and output cotangent g_v[out_at ..] to
// its columns of scratch row `row`.
void stage_layer(uint row, uint l, uint in_at, bool relu_in, uint out_at) {
  uint at = row * deform_scratch_floats(p.shape) + deform_scratch_col(p.shape, l);
  uint in_dim = deform_layer_in(p.shape, l), out_dim = deform_layer_out(p.shape, l);
  for (uint k = 0u; k < in_dim; ++k) scratch[at + k] = act_in(in_at + k, relu_in);
  for (uint o = 0u; o < out_dim; ++o) scratch[at + in_dim + o] = g_v[out_at + o];
}

// Cotangent of the layer's input pre-activation: g_v[in_at + i] (+)= ReLU'(g_act[in_at + i]) *
// sum_o weight[o][i] g_v[out_at + o] (no ReLU factor when relu_in is false).
void linear_bwd_input(uint offset, uint in_dim, uint out_dim, uint in_at, bool relu_in, uint out_at, bool accumulate) {
  for (uint i = 0u; i < in_dim; ++i) {
    float acc = 0.0;
    for (uint o = 0u; o < out_dim; ++o) acc += mlp[offset + o * in_dim + i] * g_v[out_at + o];
    if (relu_in && g_act[in_at + i] <= 0.0) acc = 0.0;
    g_v[in_at + i] = accumulate ? g_v[in_at + i] + acc : acc;
  }
}

// dL/d head h's output for Gaussian i into g_v[ACT_Y2 ..].
void load_head_cotangent(uint h, uint i) {
  uint count = deform_head_out(h);
  for (uint k = 0u; k < count; ++k) {
    float v;
    if (h == 0u) v = v_means[3u * i + k];
    else if (h == 1u) v = v_log_scales[3u * i + k];
    else if (h == 2u) v = v_quats[4u * i + k];
    else if (h == 3u) v = v_opacity[i];
    else v = v_sh[i * 3u * p.sh_coeffs + k];
    g_v[ACT_Y2 + k] = v;
  }
}

// Backward of deform_features from g_v[ACT_FEAT ..]: scatters the plane gradients, returns dL/d xyz.
vec3 deform_features_bwd(vec4 g) {
  uint C = p.shape.channels, offset = 0u;
  vec3 v_xyz = vec3(0.0);
  for (uint l = 0u; l < p.shape.levels; ++l) {
    DeformTap taps[S4D_DEFORM_PLANES];
    for (uint plane = 0u; plane < uint(S4D_DEFORM_PLANES); ++plane) {
      taps[plane] = deform_tap(l, plane, g, offset);
      for (uint c = 0u; c < C; ++c) g_samples[plane * C + c] = tap_value(taps[plane], c);
      offset += deform_plane_floats(p.shape, l, plane);
    }
    for (uint plane = 0u; plane < uint(S4D_DEFORM_PLANES); ++plane) {
      DeformTap t = taps[plane];
      float v_ix = 0.0, v_iy = 0.0;
      for (uint c = 0u; c < C; ++c) {
        float others = g_v[ACT_FEAT + l * C + c];  // dL/d sample: v_feat times the other five samples
        for (uint q = 0u; q < uint(S4D_DEFORM_PLANES); ++q)
          if (q != plane) others *= g_samples[q * C + c];
        uint i = t.base + c;
        add_v_planes(i, (1.0 - t.wx) * (1.0 - t.wy) * others);
        add_v_planes(i + t.step_x, t.wx * (1.0 - t.wy) * others);
        add_v_planes(i + t.step_y, (1.0 - t.wx) * t.wy * others);
        add_v_planes(i + t.step_y + t.step_x, t.wx * t.wy * others);
        float v00 = planes[i], v10 = planes[i + t.step_x], v01 = planes[i + t.step_y];
        float v11 = planes[i + t.step_y + t.step_x];
        v_ix += others * ((1.0 - t.wy) * (v10 - v00) + t.wy * (v11 - v01));
        v_iy += others * ((1.0 - t.wx) * (v01 - v00) + t.wx * (v11 - v10));
      }
      uint au = S4D_DEFORM_PLANE_AXIS_U(plane), av = S4D_DEFORM_PLANE_AXIS_V(plane);
      if (au < 3u) v_xyz[au] += v_ix * t.dix * p.aabb_scale[au];  // time carries no gradient
      if (av < 3u) v_xyz[av] += v_iy * t.diy * p.aabb_scale[av];
    }
  }
  return v_xyz;
}

void main() {
  uint row = flat_group_id() * S4D_DEFORM_WG + gl_LocalInvocationIndex, i = p.first + row;
  if (i >= p.n) return;
  vec4 g = deform_coords(vec3(means[3u * i], means[3u * i + 1u], means[3u * i + 2u]));
  deform_features(g);
  trunk_fwd();

  uint W = p.shape.width, last = ACT_Z(p.shape.trunk_extra);
  for (uint k = 0u; k < W; ++k) g_v[last + k] = 0.0;
  uint l = p.shape.trunk_extra + 1u;  // layer index of the next head's hidden layer
  for (uint h = 0u; h < uint(S4D_DEFORM_HEADS); ++h) {
    if (!deform_head_on(p.shape, h)) continue;
    uint o1 = deform_head_offset(p.shape, h), o2 = o1 + deform_linear_floats(W, W), out_dim = deform_head_out(h);
    head_hidden_fwd(h);
    load_head_cotangent(h, i);
    stage_layer(row, l + 1u, ACT_Y1, true, ACT_Y2);
    linear_bwd_input(o2, W, out_dim, ACT_Y1, true, ACT_Y2, false);
    stage_layer(row, l, last, true, ACT_Y1);
    linear_bwd_input(o1, W, W, last, true, ACT_Y1, true);
    l += 2u;
  }
  for (uint e = p.shape.trunk_extra; e >= 1u; --e) {
    uint o = deform_trunk_offset(p.shape, e);
    stage_layer(row, e, ACT_Z(e - 1u), true, ACT_Z(e));
    linear_bwd_input(o, W, W, ACT_Z(e - 1u), true, ACT_Z(e), false);
  }
  uint F = deform_feat_dim(p.shape);
  stage_layer(row, 0u, ACT_FEAT, false, ACT_Z(0u));
  linear_bwd_input(deform_trunk_offset(p.shape, 0u), F, W, ACT_FEAT, false, ACT_Z(0u), false);
  vec3 v_xyz = deform_features_bwd(g);
  for (uint k = 0u; k < 3u; ++k) v_means[3u * i + k] += v_xyz[k];
}
