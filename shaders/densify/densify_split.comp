// densify_split: geometry of split children (graphdeco densify_and_split with N = 2). One thread per
// output slot; slots that are not children return. For child c of source i:
//   n ~ N(0, I), three normals from Box-Muller on counter-based PCG bits (seed, i, c, draw 0..3);
//   mean = R(q / |q|) (exp(log_scale) * n) + mean_i;  log_scale = log_scale_i - log(1.6).
// Runs after densify_gather copied every attribute, and overwrites the children's means and log-scales.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "s4d_densify.h"
#include "flat_group.glsl"
#include "quat_normalise.glsl"

layout(local_size_x = S4D_DENSIFY_WG) in;
layout(push_constant) uniform Push { SplitParams p; };
layout(std430, binding = S4D_B_SPLIT_SLOTS) readonly buffer Slots { uint slots[]; };                 // [M]
layout(std430, binding = S4D_B_SPLIT_MEANS) readonly buffer Means { float means[]; };               // [N*3]
layout(std430, binding = S4D_B_SPLIT_LOG_SCALES) readonly buffer LogScales { float log_scales[]; };  // [N*3]
layout(std430, binding = S4D_B_SPLIT_QUATS) readonly buffer Quats { float quats[]; };               // [N*4]
layout(std430, binding = S4D_B_SPLIT_OUT_MEANS) buffer OutMeans { float out_means[]; };             // [M*3]
layout(std430, binding = S4D_B_SPLIT_OUT_LOG_SCALES) buffer OutLogScales { float out_log_scales[]; };  // [M*3]

const float kTwoPi = 6.28318530717958647692;

// Uniform in (0, 1]: the top 24 bits, so log() never sees 0.
float uniform01(uint bits) { return (float(bits >> 8) + 1.0) * (1.0 / 16777216.0); }

void main() {
  uint j = flat_group_id() * S4D_DENSIFY_WG + gl_LocalInvocationIndex;
  if (j >= p.n) return;
  uint slot = slots[j];
  uint kind = slot >> S4D_DENSIFY_SLOT_SHIFT;
  if (kind != S4D_DENSIFY_SLOT_CHILD0 && kind != S4D_DENSIFY_SLOT_CHILD1) return;
  uint i = slot & S4D_DENSIFY_SLOT_INDEX_MASK;
  uint child = kind - S4D_DENSIFY_SLOT_CHILD0;

  float u0 = uniform01(densify_random_bits(p.seed, i, child, 0u));
  float u1 = uniform01(densify_random_bits(p.seed, i, child, 1u));
  float u2 = uniform01(densify_random_bits(p.seed, i, child, 2u));
  float u3 = uniform01(densify_random_bits(p.seed, i, child, 3u));
  float r0 = sqrt(-2.0 * log(u0)), r1 = sqrt(-2.0 * log(u2));
  vec3 n = vec3(r0 * cos(kTwoPi * u1), r0 * sin(kTwoPi * u1), r1 * cos(kTwoPi * u3));

  vec3 ls = vec3(log_scales[3 * i], log_scales[3 * i + 1], log_scales[3 * i + 2]);
  vec3 d = exp(ls) * n;
  vec4 q = vec4(quats[4 * i], quats[4 * i + 1], quats[4 * i + 2], quats[4 * i + 3]);
  float norm;
  splat_normalise_quat(q, q, norm);
  float w = q.x, x = q.y, y = q.z, z = q.w;
  // Rows of R(q), graphdeco build_rotation.
  vec3 row0 = vec3(1.0 - 2.0 * (y * y + z * z), 2.0 * (x * y - w * z), 2.0 * (x * z + w * y));
  vec3 row1 = vec3(2.0 * (x * y + w * z), 1.0 - 2.0 * (x * x + z * z), 2.0 * (y * z - w * x));
  vec3 row2 = vec3(2.0 * (x * z - w * y), 2.0 * (y * z + w * x), 1.0 - 2.0 * (x * x + y * y));
  out_means[3 * j] = dot(row0, d) + means[3 * i];
  out_means[3 * j + 1] = dot(row1, d) + means[3 * i + 1];
  out_means[3 * j + 2] = dot(row2, d) + means[3 * i + 2];
  for (uint k = 0u; k < 3u; ++k) {
    precise float shrunk = log_scales[3 * i + k] - p.log_split_shrink;
    out_log_scales[3 * j + k] = shrunk;
  }
}
