// Densification of a Gaussian cloud in training (ALGORITHMS.md 2.2, 3.3) on the GPU: the per-view
// statistics, graphdeco's clone / split / prune with a growth budget, and the opacity reset. Its CPU
// twin is training/ref/include/s4d/ref/densify_ref.h; kernels are shaders/densify/*.comp.
#pragma once
#include <cstdint>
#include <string>

#include "s4d/engine/buffer.h"
#include "s4d/engine/context.h"
#include "s4d/engine/recorder.h"
#include "s4d/model/trainable_gaussians.h"
#include "s4d/primitives/radix_sort.h"
#include "s4d/splat/rasterizer.h"
#include "s4d_densify.h"

namespace s4d::densify {

struct DensifyRules {
  float grad_threshold = 0.0002f;  // mean NDC-space gradient norm that triggers growth
  float dense_scale = 0;           // percent_dense * extent: clone when max(scale) <= this, else split
  float min_opacity = 0.005f;      // prune below (sigmoid of the logit)
  float max_screen_radius = 0;     // prune when max_radius > this (pixels); 0 = off
  float max_world_scale = 0;       // prune when max(scale) > this; 0 = off
  bool grow = true;                // clone and split
  bool prune = true;               // the three prune rules
  uint32_t budget = UINT32_MAX;    // at most this many Gaussians after the call (growth is demoted to fit;
                                   // Gaussians that survive pruning are never removed for it)
  uint32_t seed = 0;               // split samples
  // true (graphdeco): every statistic of the result is zero. false: surviving originals keep their
  // statistics and new entries start at zero (4DGaussians' separate prune call, grow = false).
  bool reset_statistics = true;
};

// Counts of one densify() call: after = before + cloned + split - pruned. `split` counts sources
// replaced by two children; `pruned` counts entries removed by the prune rules among the originals
// kept, the copies and the children; `demoted` counts growth candidates turned plain by the budget.
struct DensifyResult {
  uint32_t before = 0, cloned = 0, split = 0, pruned = 0, demoted = 0, after = 0;
};

// The kernels' push constants for `rules` over n Gaussians (what the twin takes). Throws
// std::invalid_argument for negative or NaN thresholds.
gpu::ClassifyParams classify_params(const DensifyRules& rules, uint32_t n);

class Densifier {
 public:
  explicit Densifier(engine::Context& ctx, std::string name = "densifier");

  // Adds one view's statistics (after Rasterizer::backward of that view): for Gaussians with radius > 0,
  // grad_accum += |grad2d_xy * (W/2, H/2)|, grad_count += 1, max_radius = max(max_radius, radius).
  void record_accumulate(engine::Recorder& rec, model::TrainableGaussians& g, const splat::Rasterizer& r) const;

  // 4DGaussians' batched statistic (ALGORITHMS.md 3.3): record_accumulate_batch_add after each view's
  // backward, then record_accumulate_batch_end once per batch: for Gaussians seen by any view,
  // grad_accum += |sum of the views' NDC gradients|, grad_count += 1, max_radius = max(max_radius,
  // largest radius). `scratch` comes from make_batch_scratch(g.size()) and is zeroed again by
  // batch_end; make a new one whenever the cloud's size changes (after densify()).
  engine::Buffer make_batch_scratch(uint32_t count) const;
  void record_accumulate_batch_add(engine::Recorder& rec, const model::TrainableGaussians& g, const splat::Rasterizer& r,
                                   const engine::Buffer& scratch) const;
  void record_accumulate_batch_end(engine::Recorder& rec, model::TrainableGaussians& g, const engine::Buffer& scratch) const;

  // Clone, split, prune under `rules`, compacting every array with a prefix scan; runs and waits.
  // Statistics of the result are zero (unless rules.reset_statistics is false). Adam moments of clones and split children are zero, kept
  // Gaussians keep theirs (graphdeco semantics). Output order is stable: each source's outputs in
  // source order (original or child 0, then copy or child 1).
  DensifyResult densify(model::TrainableGaussians& g, const DensifyRules& rules);

  // opacity <- min(opacity, max_opacity) (as logits), opacity moments of every Gaussian zeroed; runs and waits.
  void reset_opacity(model::TrainableGaussians& g, float max_opacity = 0.01f);

 private:
  void reserve(uint32_t n);
  engine::Buffer buffer(const std::string& what, size_t bytes) const;

  engine::Context* ctx_;
  std::string name_;
  uint32_t capacity_ = 0;
  engine::Buffer flags_, counts_, keys_, values_, reduction_, sorted_reduction_, scan_scratch_, tally_;
  primitives::RadixSortScratch sort_;
};

}  // namespace s4d::densify
