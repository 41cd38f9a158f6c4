// Host side of densification: the order of the densify kernels (shaders/densify/*.comp) and the
// buffers between them.
//
// densify() takes up to three submissions:
//   1. densify_classify (decision word, outputs, sort key and saving per source), exclusive scan of
//      the outputs; the host reads the total (4 bytes).
//   2. Only when the total exceeds the budget: radix sort of the candidates' keys, densify_gather of
//      their savings into sorted order, exclusive scan, densify_demote (which also rewrites every
//      output count), scan again; the host reads the new total.
//   3. densify_map (slot words at the scanned offsets), densify_gather over every parameter and Adam
//      moment array (moments of new entries zeroed), densify_split over the children; statistics are
//      filled with zeros. The host reads the tally and swaps the new arrays in.
#include "s4d/densify/densifier.h"

#include <array>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "s4d/primitives/scan.h"
#include "s4d/primitives/shader_pipeline.h"
#include "s4d_splat.h"

namespace s4d::densify {
namespace {

using model::Attr;
using model::Stat;

uint32_t groups(uint64_t threads) { return primitives::ceil_div(threads, S4D_DENSIFY_WG); }

void check_rule(float value, const char* what) {
  if (!(value >= 0)) throw std::invalid_argument(std::string("densify: ") + what + " must be >= 0 (got " + std::to_string(value) + ")");
}

}  // namespace

gpu::ClassifyParams classify_params(const DensifyRules& rules, uint32_t n) {
  check_rule(rules.grad_threshold, "grad_threshold");
  check_rule(rules.dense_scale, "dense_scale");
  check_rule(rules.min_opacity, "min_opacity");
  check_rule(rules.max_screen_radius, "max_screen_radius");
  check_rule(rules.max_world_scale, "max_world_scale");
  return gpu::densify_classify_params(n, rules.grad_threshold, rules.dense_scale, rules.min_opacity, rules.max_screen_radius,
                                      rules.max_world_scale, rules.grow, rules.prune);
}

Densifier::Densifier(engine::Context& ctx, std::string name) : ctx_(&ctx), name_(std::move(name)) {
  tally_ = buffer("tally", S4D_DENSIFY_TALLY_COUNT * 4);
}

engine::Buffer Densifier::buffer(const std::string& what, size_t bytes) const {
  return engine::Buffer(*ctx_, name_ + " " + what, bytes);
}

void Densifier::reserve(uint32_t n) {
  if (n <= capacity_ && flags_.valid()) return;
  const uint32_t cap = n + n / 4;  // headroom: the cloud grows between calls
  const size_t c = cap;
  flags_ = buffer("flags", c * 4);
  counts_ = buffer("output offsets", (c + 1) * 4);
  keys_ = buffer("demotion keys", c * 4);
  values_ = buffer("demotion order", c * 4);
  reduction_ = buffer("demotion savings", c * 4);
  sorted_reduction_ = buffer("sorted savings", c * 4);
  scan_scratch_ = buffer("scan scratch", primitives::scan_scratch_bytes(cap + 1));
  sort_ = primitives::RadixSortScratch(*ctx_, cap, name_ + " demotion sort");
  capacity_ = cap;
}

namespace {

void check_views(const model::TrainableGaussians& g, const splat::Rasterizer& r, const char* what) {
  const size_t n = g.size();
  if (r.grad2d().size() < n * S4D_G2D_STRIDE * 4 || r.info().size() < n * 16)
    throw std::invalid_argument(std::string("densify: ") + what + ": the rasterizer's buffers hold fewer than " +
                                std::to_string(n) + " Gaussians (render and backward this cloud first)");
  if (r.camera().width == 0 || r.camera().height == 0)
    throw std::invalid_argument(std::string("densify: ") + what + ": the rasterizer has not rendered a view");
}

gpu::AccumulateParams accumulate_params(uint32_t n, uint32_t mode, const splat::Camera& cam) {
  return {.n = n,
          .mode = mode,
          .half_width = static_cast<float>(cam.width) / 2,
          .half_height = static_cast<float>(cam.height) / 2};
}

}  // namespace

void Densifier::record_accumulate(engine::Recorder& rec, model::TrainableGaussians& g, const splat::Rasterizer& r) const {
  check_views(g, r, "record_accumulate");
  const uint32_t n = g.size();
  const engine::Buffer& accum = g.stat(model::kGradAccum);
  rec.dispatch(primitives::shader_pipeline(*ctx_, shaders::Id::densify_accumulate),
               {S4D_BIND(ACCUM_GRAD2D, r.grad2d()), S4D_BIND(ACCUM_INFO, r.info()), S4D_BIND(ACCUM_GRAD_ACCUM, accum),
                S4D_BIND(ACCUM_GRAD_COUNT, g.stat(model::kGradCount)),
                S4D_BIND(ACCUM_MAX_RADIUS, g.stat(model::kMaxRadius)), S4D_BIND(ACCUM_SCRATCH, accum)},  // no scratch
               accumulate_params(n, S4D_ACCUM_VIEW, r.camera()), groups(n));
}

engine::Buffer Densifier::make_batch_scratch(uint32_t count) const {
  engine::Buffer s = buffer("batch scratch", size_t{count} * S4D_ACCUM_SCRATCH_STRIDE * 4);
  engine::Recorder rec(*ctx_, name_ + " batch scratch");
  rec.fill(s, 0);
  ctx_->run(std::move(rec));
  return s;
}

void Densifier::record_accumulate_batch_add(engine::Recorder& rec, const model::TrainableGaussians& g,
                                            const splat::Rasterizer& r, const engine::Buffer& scratch) const {
  check_views(g, r, "record_accumulate_batch_add");
  const uint32_t n = g.size();
  if (scratch.size() < size_t{n} * S4D_ACCUM_SCRATCH_STRIDE * 4)
    throw std::invalid_argument("densify: batch scratch '" + scratch.name() + "' is smaller than " + std::to_string(n) + " Gaussians need");
  rec.dispatch(primitives::shader_pipeline(*ctx_, shaders::Id::densify_accumulate),
               {S4D_BIND(ACCUM_GRAD2D, r.grad2d()), S4D_BIND(ACCUM_INFO, r.info()),
                S4D_BIND(ACCUM_GRAD_ACCUM, scratch), S4D_BIND(ACCUM_GRAD_COUNT, scratch),
                S4D_BIND(ACCUM_MAX_RADIUS, scratch), S4D_BIND(ACCUM_SCRATCH, scratch)},  // the statistics are not touched
               accumulate_params(n, S4D_ACCUM_BATCH_ADD, r.camera()), groups(n));
}

void Densifier::record_accumulate_batch_end(engine::Recorder& rec, model::TrainableGaussians& g,
                                            const engine::Buffer& scratch) const {
  const uint32_t n = g.size();
  if (scratch.size() < size_t{n} * S4D_ACCUM_SCRATCH_STRIDE * 4)
    throw std::invalid_argument("densify: batch scratch '" + scratch.name() + "' is smaller than " + std::to_string(n) + " Gaussians need");
  const gpu::AccumulateParams p{.n = n, .mode = S4D_ACCUM_BATCH_END, .half_width = 0, .half_height = 0};
  rec.dispatch(
      primitives::shader_pipeline(*ctx_, shaders::Id::densify_accumulate),
      {S4D_BIND(ACCUM_GRAD2D, scratch), S4D_BIND(ACCUM_INFO, scratch),
       S4D_BIND(ACCUM_GRAD_ACCUM, g.stat(model::kGradAccum)), S4D_BIND(ACCUM_GRAD_COUNT, g.stat(model::kGradCount)),
       S4D_BIND(ACCUM_MAX_RADIUS, g.stat(model::kMaxRadius)), S4D_BIND(ACCUM_SCRATCH, scratch)},
      p, groups(n));
}

DensifyResult Densifier::densify(model::TrainableGaussians& g, const DensifyRules& rules) {
  const uint32_t n = g.size();
  const gpu::ClassifyParams cp = classify_params(rules, n);
  DensifyResult result;
  result.before = n;
  if (n == 0) return result;
  if (n >= S4D_DENSIFY_MAX_GAUSSIANS)
    throw std::invalid_argument("densify: " + std::to_string(n) + " Gaussians; slot words address fewer than 2^30");
  reserve(n);
  engine::Context& ctx = *ctx_;

  // 1. Decide, count outputs, scan.
  {
    engine::Recorder rec(ctx, name_ + " classify");
    rec.begin_label("densify classify");
    rec.fill(tally_, 0);
    rec.dispatch(
        primitives::shader_pipeline(ctx, shaders::Id::densify_classify),
        {S4D_BIND(CLASSIFY_LOG_SCALES, g.param(Attr::log_scales)),
         S4D_BIND(CLASSIFY_OPACITY, g.param(Attr::opacity_logits)), S4D_BIND(CLASSIFY_GRAD_ACCUM, g.stat(model::kGradAccum)),
         S4D_BIND(CLASSIFY_GRAD_COUNT, g.stat(model::kGradCount)),
         S4D_BIND(CLASSIFY_MAX_RADIUS, g.stat(model::kMaxRadius)), S4D_BIND(CLASSIFY_FLAGS, flags_),
         S4D_BIND(CLASSIFY_COUNTS, counts_), S4D_BIND(CLASSIFY_KEYS, keys_), S4D_BIND(CLASSIFY_VALUES, values_),
         S4D_BIND(CLASSIFY_REDUCTION, reduction_)},
        cp, groups(n));
    rec.barrier();
    primitives::cmd_exclusive_scan(rec, counts_, n + 1, scan_scratch_);
    rec.end_label();
    ctx.run(std::move(rec));
  }
  uint32_t total = ctx.download<uint32_t>(counts_, 1, n)[0];

  // 2. Budget: demote the candidates with the lowest mean gradients until the result fits.
  if (total > rules.budget) {
    engine::Recorder rec(ctx, name_ + " demote");
    rec.begin_label("densify demote");
    rec.barrier();
    primitives::cmd_radix_sort(rec, keys_, values_, n, 32, sort_);
    rec.barrier();
    const gpu::SlotParams gather{.n = n, .width = 1, .zero_new = 0, .value = 0};  // source indices are slot words of kind 0
    rec.dispatch(
        primitives::shader_pipeline(ctx, shaders::Id::densify_gather),
        {S4D_BIND(GATHER_SLOTS, values_), S4D_BIND(GATHER_SRC, reduction_), S4D_BIND(GATHER_DST, sorted_reduction_)},
        gather, groups(n));
    rec.barrier();
    primitives::cmd_exclusive_scan(rec, sorted_reduction_, n, scan_scratch_);
    rec.barrier();
    const gpu::DemoteParams dp{.n = n, .excess = total - rules.budget, ._pad0 = 0, ._pad1 = 0};
    rec.dispatch(primitives::shader_pipeline(ctx, shaders::Id::densify_demote),
                 {S4D_BIND(DEMOTE_VALUES, values_), S4D_BIND(DEMOTE_PREFIX, sorted_reduction_),
                  S4D_BIND(DEMOTE_REDUCTION, reduction_), S4D_BIND(DEMOTE_FLAGS, flags_),
                  S4D_BIND(DEMOTE_COUNTS, counts_), S4D_BIND(DEMOTE_TALLY, tally_)},
                 dp, groups(n));
    rec.barrier();
    primitives::cmd_exclusive_scan(rec, counts_, n + 1, scan_scratch_);
    rec.end_label();
    ctx.run(std::move(rec));
    total = ctx.download<uint32_t>(counts_, 1, n)[0];
  }

  // 3. Map output slots to sources and gather every array.
  const uint32_t m = total;
  model::TrainableGaussians::Arrays next = g.allocate(m);
  {
    engine::Buffer slots = buffer("slots", size_t{m} * 4);
    engine::Recorder rec(ctx, name_ + " compact");
    rec.begin_label("densify compact");
    const gpu::SlotParams mp{.n = n, .width = 0, .zero_new = 0, .value = 0};
    rec.dispatch(primitives::shader_pipeline(ctx, shaders::Id::densify_map),
                 {S4D_BIND(MAP_FLAGS, flags_), S4D_BIND(MAP_OFFSETS, counts_), S4D_BIND(MAP_SLOTS, slots),
                  S4D_BIND(MAP_TALLY, tally_)},
                 mp, groups(n));
    if (rules.reset_statistics)
      for (engine::Buffer& s : next.stat) rec.fill(s, 0);
    if (m > 0) {
      rec.barrier();
      const engine::Pipeline& gather = primitives::shader_pipeline(ctx, shaders::Id::densify_gather);
      if (!rules.reset_statistics)
        for (uint32_t k = 0; k < model::kStatCount; ++k)
          rec.dispatch(gather,
                       {S4D_BIND(GATHER_SLOTS, slots), S4D_BIND(GATHER_SRC, g.stat(Stat(k))),
                        S4D_BIND(GATHER_DST, next.stat[k])},
                       gpu::SlotParams{.n = m, .width = 1, .zero_new = 1, .value = 0}, groups(m));
      for (Attr a : splat::kCloudAttrs) {
        const uint32_t w = g.width(a);
        if (uint64_t{m} * w >= (uint64_t{1} << 32))
          throw std::invalid_argument(std::string("densify: ") + splat::attr_name(a) + " of " + std::to_string(m) +
                                      " Gaussians exceeds 2^32 words");
        const gpu::SlotParams copy{.n = m, .width = w, .zero_new = 0, .value = 0};
        const gpu::SlotParams fresh_zero{.n = m, .width = w, .zero_new = 1, .value = 0};
        rec.dispatch(gather,
                     {S4D_BIND(GATHER_SLOTS, slots), S4D_BIND(GATHER_SRC, g.param(a)),
                      S4D_BIND(GATHER_DST, next.param[a])},
                     copy, groups(uint64_t{m} * w));
        rec.dispatch(
            gather,
            {S4D_BIND(GATHER_SLOTS, slots), S4D_BIND(GATHER_SRC, g.moment1(a)), S4D_BIND(GATHER_DST, next.m[a])},
            fresh_zero, groups(uint64_t{m} * w));
        rec.dispatch(
            gather,
            {S4D_BIND(GATHER_SLOTS, slots), S4D_BIND(GATHER_SRC, g.moment2(a)), S4D_BIND(GATHER_DST, next.v[a])},
            fresh_zero, groups(uint64_t{m} * w));
      }
      rec.barrier();
      const gpu::SplitParams sp{.n = m, .seed = rules.seed, .log_split_shrink = cp.log_split_shrink, ._pad0 = 0};
      rec.dispatch(primitives::shader_pipeline(ctx, shaders::Id::densify_split),
                   {S4D_BIND(SPLIT_SLOTS, slots), S4D_BIND(SPLIT_MEANS, g.param(Attr::means)),
                    S4D_BIND(SPLIT_LOG_SCALES, g.param(Attr::log_scales)),
                    S4D_BIND(SPLIT_QUATS, g.param(Attr::quats)), S4D_BIND(SPLIT_OUT_MEANS, next.param[Attr::means]),
                    S4D_BIND(SPLIT_OUT_LOG_SCALES, next.param[Attr::log_scales])},
                   sp, groups(m));
    }
    rec.end_label();
    ctx.run(std::move(rec));
  }
  const std::vector<uint32_t> tally = ctx.download<uint32_t>(tally_, S4D_DENSIFY_TALLY_COUNT);
  result.cloned = tally[S4D_DENSIFY_TALLY_CLONED];
  result.split = tally[S4D_DENSIFY_TALLY_SPLIT];
  result.pruned = tally[S4D_DENSIFY_TALLY_PRUNED];
  result.demoted = tally[S4D_DENSIFY_TALLY_DEMOTED];
  result.after = m;
  g.adopt(std::move(next), m);
  return result;
}

void Densifier::reset_opacity(model::TrainableGaussians& g, float max_opacity) {
  if (!(max_opacity >= 0 && max_opacity <= 1))
    throw std::invalid_argument("densify: reset_opacity needs 0 <= max_opacity <= 1 (got " + std::to_string(max_opacity) + ")");
  const uint32_t n = g.size();
  if (n == 0) return;
  engine::Recorder rec(*ctx_, name_ + " reset opacity");
  const gpu::SlotParams p{.n = n, .width = 1, .zero_new = 0, .value = gpu::densify_reset_logit(max_opacity)};
  rec.dispatch(primitives::shader_pipeline(*ctx_, shaders::Id::densify_reset_opacity),
               {S4D_BIND(RESET_OPACITY, g.param(Attr::opacity_logits)), S4D_BIND(RESET_M, g.moment1(Attr::opacity_logits)),
                S4D_BIND(RESET_V, g.moment2(Attr::opacity_logits))},
               p, groups(n));
  ctx_->run(std::move(rec));
}

}  // namespace s4d::densify
