// densify_classify: the per-Gaussian decision of graphdeco's densify_and_prune (ALGORITHMS.md 2.2).
// One thread per source Gaussian:
//   mean_grad = accum / count (0 when count = 0); grow when mean_grad >= threshold, tested as
//   accum >= threshold * count so the GPU and the twin agree without a division;
//   clone when max(log_scale) <= log(dense_scale), else split;
//   prune the original when logit < logit(min_opacity), max_radius > max_screen_radius or
//   max(log_scale) > log(max_world_scale) (each rule only when enabled); a new entry (copy or split
//   child) is tested with max_radius 0 and, for a child, its shrunken log_scale.
// Writes the decision word, the number of outputs, and for growth candidates whose demotion would
// save outputs the sort key (mean_grad's bits: ascending float order for non-negative floats), the
// source index and the outputs saved. Thread 0 also zeroes counts[N] so the scan yields the total.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "s4d_densify.h"
#include "flat_group.glsl"

layout(local_size_x = S4D_DENSIFY_WG) in;
layout(push_constant) uniform Push { ClassifyParams p; };
layout(std430, binding = S4D_B_CLASSIFY_LOG_SCALES) readonly buffer LogScales { float log_scales[]; };  // [N*3]
layout(std430, binding = S4D_B_CLASSIFY_OPACITY) readonly buffer Opacity { float opacity_logits[]; };  // [N]
layout(std430, binding = S4D_B_CLASSIFY_GRAD_ACCUM) readonly buffer Accum { float grad_accum[]; };     // [N]
layout(std430, binding = S4D_B_CLASSIFY_GRAD_COUNT) readonly buffer Count { float grad_count[]; };     // [N]
layout(std430, binding = S4D_B_CLASSIFY_MAX_RADIUS) readonly buffer Radius { float max_radius[]; };    // [N]
layout(std430, binding = S4D_B_CLASSIFY_FLAGS) writeonly buffer Flags { uint flags[]; };              // [N]
layout(std430, binding = S4D_B_CLASSIFY_COUNTS) writeonly buffer Counts { uint counts[]; };           // [N + 1]
layout(std430, binding = S4D_B_CLASSIFY_KEYS) writeonly buffer Keys { uint keys[]; };                 // [N]
layout(std430, binding = S4D_B_CLASSIFY_VALUES) writeonly buffer Values { uint values[]; };           // [N]
layout(std430, binding = S4D_B_CLASSIFY_REDUCTION) writeonly buffer Reduction { uint reduction[]; };  // [N]

void main() {
  uint i = flat_group_id() * S4D_DENSIFY_WG + gl_LocalInvocationIndex;
  if (i == 0u) counts[p.n] = 0u;
  if (i >= p.n) return;
  float max_ls = max(max(log_scales[3 * i], log_scales[3 * i + 1]), log_scales[3 * i + 2]);
  float accum = grad_accum[i], count = grad_count[i];
  precise float needed = p.grad_threshold * count;
  bool grow = (p.rules & S4D_DENSIFY_RULE_GROW) != 0u && (count > 0.0 ? accum >= needed : 0.0 >= p.grad_threshold);

  bool faint = (p.rules & S4D_DENSIFY_RULE_PRUNE_OPACITY) != 0u && opacity_logits[i] < p.logit_min_opacity;
  bool world = (p.rules & S4D_DENSIFY_RULE_PRUNE_WORLD) != 0u;
  bool screen = (p.rules & S4D_DENSIFY_RULE_PRUNE_SCREEN) != 0u;
  bool orig_dies = faint || (screen && max_radius[i] > p.max_screen_radius) || (world && max_ls > p.log_max_world_scale);

  uint f = orig_dies ? 0u : S4D_DENSIFY_ORIG_LIVES;
  if (grow) {
    bool clone = max_ls <= p.log_dense_scale;
    precise float child_ls = max_ls - p.log_split_shrink;
    float new_ls = clone ? max_ls : child_ls;
    bool new_dies = faint || (screen && 0.0 > p.max_screen_radius) || (world && new_ls > p.log_max_world_scale);
    f |= (clone ? S4D_DENSIFY_CLONE : S4D_DENSIFY_SPLIT) | (new_dies ? 0u : S4D_DENSIFY_NEW_LIVES);
  }
  uint outputs = densify_output_count(f);
  uint plain = densify_output_count(f & ~S4D_DENSIFY_GROW_MASK);
  uint saved = outputs - plain;  // never negative: a new entry passes every rule its original passes but the radius
  flags[i] = f;
  counts[i] = outputs;
  reduction[i] = saved;
  float mean_grad = count > 0.0 ? accum / count : 0.0;
  keys[i] = saved > 0u ? floatBitsToUint(mean_grad) : S4D_DENSIFY_NOT_CANDIDATE_KEY;
  values[i] = i;
}
