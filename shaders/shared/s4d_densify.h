// Shared layouts, constants and integer helpers of densification (ALGORITHMS.md 2.2, 3.3): the
// statistics kernel, clone / split / prune with a growth budget, and the opacity reset. The CPU twin
// (training/ref/include/s4d/ref/densify_ref.h) calls the same helpers, so the per-Gaussian decisions,
// the output layout and the split samples' random bits are identical by construction.
#ifndef S4D_DENSIFY_H
#define S4D_DENSIFY_H
#include "s4d_common.h"

#ifdef __cplusplus
#define S4D_DENSIFY_FN inline
#else
#define S4D_DENSIFY_FN
#endif

#define S4D_DENSIFY_WG 256

// Per-source decision word written by densify_classify (and rewritten by densify_demote).
#define S4D_DENSIFY_GROW_MASK 3u    // bits 0-1: S4D_DENSIFY_KEEP, _CLONE or _SPLIT
#define S4D_DENSIFY_KEEP 0u         // no growth: the original alone
#define S4D_DENSIFY_CLONE 1u        // the original and an exact copy
#define S4D_DENSIFY_SPLIT 2u        // two children replace the original
#define S4D_DENSIFY_ORIG_LIVES 4u   // bit 2: the original survives the prune rules
#define S4D_DENSIFY_NEW_LIVES 8u    // bit 3: a new entry (copy or child) survives the prune rules

// Output slot word written by densify_map: source index | kind << 30, so at most 2^30 Gaussians.
#define S4D_DENSIFY_SLOT_SHIFT 30u
#define S4D_DENSIFY_SLOT_INDEX_MASK 0x3FFFFFFFu
#define S4D_DENSIFY_SLOT_ORIGINAL 0u  // the source itself (keeps its Adam moments)
#define S4D_DENSIFY_SLOT_COPY 1u      // the clone's copy
#define S4D_DENSIFY_SLOT_CHILD0 2u    // split children
#define S4D_DENSIFY_SLOT_CHILD1 3u
#define S4D_DENSIFY_MAX_GAUSSIANS 0x40000000u

// Sort key of a Gaussian that is not a demotable growth candidate: after every finite mean gradient.
#define S4D_DENSIFY_NOT_CANDIDATE_KEY 0xFFFFFFFFu

// ClassifyParams.flags
#define S4D_DENSIFY_RULE_GROW 1u          // clone and split
#define S4D_DENSIFY_RULE_PRUNE_OPACITY 2u // sigmoid(logit) < min_opacity
#define S4D_DENSIFY_RULE_PRUNE_SCREEN 4u  // max_radius > max_screen_radius
#define S4D_DENSIFY_RULE_PRUNE_WORLD 8u   // max(scale) > max_world_scale

// Tally counters (u32 each, zeroed before densify_demote and densify_map).
#define S4D_DENSIFY_TALLY_CLONED 0
#define S4D_DENSIFY_TALLY_SPLIT 1
#define S4D_DENSIFY_TALLY_PRUNED 2
#define S4D_DENSIFY_TALLY_DEMOTED 3
#define S4D_DENSIFY_TALLY_COUNT 4

// densify_accumulate modes: one view straight into the statistics, or 4DGaussians' batch (sum each
// view's screen gradient into a scratch, then one statistics update per batch from the sum's norm).
#define S4D_ACCUM_VIEW 0u
#define S4D_ACCUM_BATCH_ADD 1u
#define S4D_ACCUM_BATCH_END 2u
#define S4D_ACCUM_SCRATCH_STRIDE 3   // per Gaussian: summed NDC gradient x, y; largest radius seen

// Binding ids.
#define S4D_B_ACCUM_GRAD2D 0       // [N*S4D_G2D_STRIDE] f32 raster_bwd cotangents (BATCH_END: unused)
#define S4D_B_ACCUM_INFO 1         // [N] uvec4 project_fwd info, .z = pixel radius (BATCH_END: unused)
#define S4D_B_ACCUM_GRAD_ACCUM 2   // [N] f32 statistics, updated in place (BATCH_ADD: unused)
#define S4D_B_ACCUM_GRAD_COUNT 3   // [N] f32
#define S4D_B_ACCUM_MAX_RADIUS 4   // [N] f32
#define S4D_B_ACCUM_SCRATCH 5      // [N*S4D_ACCUM_SCRATCH_STRIDE] f32 batch sums (VIEW: unused)

#define S4D_B_CLASSIFY_LOG_SCALES 0  // [N*3] f32
#define S4D_B_CLASSIFY_OPACITY 1     // [N] f32 logits
#define S4D_B_CLASSIFY_GRAD_ACCUM 2  // [N] f32
#define S4D_B_CLASSIFY_GRAD_COUNT 3  // [N] f32
#define S4D_B_CLASSIFY_MAX_RADIUS 4  // [N] f32
#define S4D_B_CLASSIFY_FLAGS 5       // out [N] u32 decision words
#define S4D_B_CLASSIFY_COUNTS 6      // out [N + 1] u32 outputs per source ([N] = 0), scanned afterwards
#define S4D_B_CLASSIFY_KEYS 7        // out [N] u32 mean-gradient bits of demotable candidates
#define S4D_B_CLASSIFY_VALUES 8      // out [N] u32 source index
#define S4D_B_CLASSIFY_REDUCTION 9   // out [N] u32 outputs saved by demoting this source (0: not demotable)

#define S4D_B_DEMOTE_VALUES 0        // [N] u32 source indices in ascending mean-gradient order
#define S4D_B_DEMOTE_PREFIX 1        // [N] u32 exclusive prefix of the reductions in that order
#define S4D_B_DEMOTE_REDUCTION 2     // [N] u32 per source
#define S4D_B_DEMOTE_FLAGS 3         // [N] u32 decision words, updated
#define S4D_B_DEMOTE_COUNTS 4        // out [N + 1] u32 outputs per source after demotion ([N] = 0)
#define S4D_B_DEMOTE_TALLY 5         // [S4D_DENSIFY_TALLY_COUNT] u32

#define S4D_B_MAP_FLAGS 0            // [N] u32
#define S4D_B_MAP_OFFSETS 1          // [N + 1] u32 exclusive scan of the output counts
#define S4D_B_MAP_SLOTS 2            // out [M] u32 slot words
#define S4D_B_MAP_TALLY 3            // [S4D_DENSIFY_TALLY_COUNT] u32

#define S4D_B_GATHER_SLOTS 0         // [M] u32 slot words
#define S4D_B_GATHER_SRC 1           // [N*w] 32-bit words, copied bit for bit
#define S4D_B_GATHER_DST 2           // out [M*w]

#define S4D_B_SPLIT_SLOTS 0          // [M] u32
#define S4D_B_SPLIT_MEANS 1          // [N*3] f32 source means
#define S4D_B_SPLIT_LOG_SCALES 2     // [N*3] f32
#define S4D_B_SPLIT_QUATS 3          // [N*4] f32 (w, x, y, z), normalised here
#define S4D_B_SPLIT_OUT_MEANS 4      // [M*3] f32, children's entries overwritten
#define S4D_B_SPLIT_OUT_LOG_SCALES 5 // [M*3] f32

#define S4D_B_RESET_OPACITY 0        // [N] f32 logits, updated in place
#define S4D_B_RESET_M 1              // [N] f32 Adam first moment of the logits, zeroed
#define S4D_B_RESET_V 2              // [N] f32 second moment, zeroed

S4D_NAMESPACE_BEGIN

// Push constants of densify_accumulate.
struct AccumulateParams {
  uint n;          // Gaussians
  uint mode;       // S4D_ACCUM_*
  float half_width;   // W / 2: pixel gradient to graphdeco's NDC gradient
  float half_height;  // H / 2
};

// Push constants of densify_classify. The thresholds are compared in log space (scales) and logit
// space (opacity) so that the GPU and the twin make the same decision without exp or sigmoid.
struct ClassifyParams {
  uint n;
  uint rules;                  // S4D_DENSIFY_RULE_*
  float grad_threshold;        // grow when accum >= grad_threshold * count (count > 0)
  float log_dense_scale;       // clone when max(log_scale) <= this, else split
  float logit_min_opacity;     // prune when logit < this
  float max_screen_radius;     // prune when max_radius > this
  float log_max_world_scale;   // prune when max(log_scale) > this
  float log_split_shrink;      // children's log_scale = log_scale - this (log 1.6)
};

// Push constants of densify_demote.
struct DemoteParams {
  uint n;
  uint excess;  // outputs over the budget
  uint _pad0;
  uint _pad1;
};

// Push constants of densify_map, densify_gather (n = output slots) and densify_reset_opacity.
struct SlotParams {
  uint n;
  uint width;      // gather: words per Gaussian
  uint zero_new;   // gather: copies and children get 0 (Adam moments)
  float value;     // reset_opacity: the largest logit kept
};

// Push constants of densify_split.
struct SplitParams {
  uint n;                  // output slots
  uint seed;
  float log_split_shrink;  // log 1.6
  uint _pad0;
};

// PCG hash (Jarzynski and Olano, "Hash Functions for GPU Rendering", 2020): all 32-bit integer
// arithmetic, so the twin reproduces every bit.
S4D_DENSIFY_FN uint densify_pcg(uint v) {
  uint state = v * 747796405u + 2891336453u;
  uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
  return (word >> 22u) ^ word;
}

// Random bits of split sample `draw` (0..3) of child `child` (0, 1) of source Gaussian `index`.
S4D_DENSIFY_FN uint densify_random_bits(uint seed, uint index, uint child, uint draw) {
  return densify_pcg(densify_pcg(densify_pcg(seed) ^ index) ^ (child * 4u + draw));
}

// Outputs of a source under its decision word, in slot order.
S4D_DENSIFY_FN uint densify_output_count(uint flags) {
  uint orig = (flags & S4D_DENSIFY_ORIG_LIVES) != 0u ? 1u : 0u;
  uint fresh = (flags & S4D_DENSIFY_NEW_LIVES) != 0u ? 1u : 0u;
  uint grow = flags & S4D_DENSIFY_GROW_MASK;
  if (grow == S4D_DENSIFY_CLONE) return orig + fresh;
  if (grow == S4D_DENSIFY_SPLIT) return 2u * fresh;
  return orig;
}

// Kind of the k-th output of a source (k < densify_output_count(flags)).
S4D_DENSIFY_FN uint densify_slot_kind(uint flags, uint k) {
  uint grow = flags & S4D_DENSIFY_GROW_MASK;
  if (grow == S4D_DENSIFY_SPLIT) return k == 0u ? S4D_DENSIFY_SLOT_CHILD0 : S4D_DENSIFY_SLOT_CHILD1;
  if (grow == S4D_DENSIFY_CLONE && (k == 1u || (flags & S4D_DENSIFY_ORIG_LIVES) == 0u)) return S4D_DENSIFY_SLOT_COPY;
  return S4D_DENSIFY_SLOT_ORIGINAL;
}

// Entries the prune rules removed from a source's outputs (the split original is not counted:
// splitting, not pruning, removes it).
S4D_DENSIFY_FN uint densify_pruned_count(uint flags) {
  uint orig = (flags & S4D_DENSIFY_ORIG_LIVES) != 0u ? 0u : 1u;
  uint fresh = (flags & S4D_DENSIFY_NEW_LIVES) != 0u ? 0u : 1u;
  uint grow = flags & S4D_DENSIFY_GROW_MASK;
  if (grow == S4D_DENSIFY_CLONE) return orig + fresh;
  if (grow == S4D_DENSIFY_SPLIT) return 2u * fresh;
  return orig;
}

S4D_NAMESPACE_END

#ifdef __cplusplus
#include <cfloat>
#include <cmath>

namespace s4d::gpu {

// densify_classify's push constants from the rules in their natural units (host and twin share this,
// so both compare against the same floats). A disabled rule's threshold is left at 0.
//   dense_scale: clone at or below, split above; 0 splits every grown Gaussian.
//   min_opacity: prune below (an opacity, not a logit); max_screen_radius / max_world_scale: 0 = off.
inline ClassifyParams densify_classify_params(uint n, float grad_threshold, float dense_scale, float min_opacity,
                                              float max_screen_radius, float max_world_scale, bool grow, bool prune) {
  ClassifyParams p{};
  p.n = n;
  p.rules = grow ? S4D_DENSIFY_RULE_GROW : 0u;
  p.grad_threshold = grad_threshold;
  p.log_dense_scale = dense_scale > 0 ? static_cast<float>(std::log(double{dense_scale})) : -FLT_MAX;
  if (prune && min_opacity > 0) {
    p.rules |= S4D_DENSIFY_RULE_PRUNE_OPACITY;
    p.logit_min_opacity = min_opacity >= 1 ? FLT_MAX : static_cast<float>(std::log(min_opacity / (1.0 - min_opacity)));
  }
  if (prune && max_screen_radius > 0) {
    p.rules |= S4D_DENSIFY_RULE_PRUNE_SCREEN;
    p.max_screen_radius = max_screen_radius;
  }
  if (prune && max_world_scale > 0) {
    p.rules |= S4D_DENSIFY_RULE_PRUNE_WORLD;
    p.log_max_world_scale = static_cast<float>(std::log(double{max_world_scale}));
  }
  p.log_split_shrink = static_cast<float>(std::log(1.6));  // children's scale = s / (0.8 * 2)
  return p;
}

// logit(max_opacity) for densify_reset_opacity.
inline float densify_reset_logit(float max_opacity) {
  if (max_opacity >= 1) return FLT_MAX;
  if (max_opacity <= 0) return -FLT_MAX;
  return static_cast<float>(std::log(max_opacity / (1.0 - max_opacity)));
}

}  // namespace s4d::gpu
#endif

#endif  // S4D_DENSIFY_H
