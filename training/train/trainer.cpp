#include "s4d/train/trainer.h"

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <cmath>
#include <fstream>
#include <iostream>
#include <optional>
#include <stdexcept>

#include "s4d/data/frame_cache.h"
#include "s4d/deform/deformation_field.h"
#include "s4d/deform/static_split.h"
#include "s4d/densify/densifier.h"
#include "s4d/io/ply_gaussians.h"
#include "s4d/model/trainable_gaussians.h"
#include "s4d/optim/adam.h"
#include "s4d/optim/grad_add.h"
#include "s4d/optim/image_loss.h"
#include "s4d/optim/lr_schedule.h"
#include "s4d/splat/rasterizer.h"
#include "s4d/splat/scene_upload.h"
#include "s4d/train/checkpoint.h"
#include "s4d/train/data_recipe.h"
#include "s4d/train/init_cloud.h"
#include "s4d/train/run_lock.h"
#include "s4d/train/split_state.h"
#include "s4d/train/time_estimate.h"
#include "s4d/train/view_sampler.h"
#include "s4d/util/atomic_file.h"
#include "s4d/util/progress.h"

namespace s4d::train {

namespace fs = std::filesystem;

namespace {

constexpr size_t kFrameCacheBytes = size_t{1} << 30;
constexpr uint32_t kMaxRollbacks = 8;     // each halves the learning rates
constexpr size_t kPeriodicTestViews = 8;  // periodic tests use this many test views; the final one all
// Static steps timed for the run's time estimate, after the first ones, which compile pipelines and
// fill the frame cache (on a 2-core lavapipe the first 10 ran 3x slower than the rest).
constexpr uint32_t kProbeFrom = 20, kProbeSteps = 30;

// Adam groups: one per Gaussian attribute with the SH rows split into DC and the rest, then the
// deformation field's planes and MLP.
enum Group : uint32_t { gMeans, gScales, gQuats, gOpacity, gShDc, gShRest, gPlanes, gMlp, gCount };

// Cap on the points a run starts from: 4DGaussians downsamples its clouds to 40k, and starting at
// the Gaussian budget would leave densification no room.
uint32_t max_initial_points(const TrainConfig& c) { return std::min<uint32_t>(40000, std::max<uint32_t>(1, c.budget / 2)); }

// What train.json and run.json say about the data and the choices made from it.
nlohmann::json dataset_facts(const data::Dataset& d, const InitReport& init, const nlohmann::json& recipe) {
  nlohmann::json background = {{"value", d.background}, {"source", d.background_source}};
  if (!d.background_conflict.empty()) background["conflict"] = d.background_conflict;
  return {{"layout", d.layout},
          {"kind", d.kind},
          {"background", background},
          {"init", {{"method", init.method}, {"file", init.file}, {"file_points", init.file_points}, {"points", init.points},
                    {"voxel", init.voxel}, {"acceptance", init.acceptance}}},
          {"recipe", recipe}};
}

std::vector<const data::View*> select_views(const data::Dataset& d, const TrainConfig& c, bool test) {
  std::vector<const data::View*> out;
  for (const data::View& v : d.views)
    if (v.test == test && v.time <= c.max_time + 1e-9) out.push_back(&v);
  return out;
}

// Evenly spaced subset of at most k views, always including the first.
std::vector<const data::View*> spread(const std::vector<const data::View*>& views, size_t k) {
  if (views.size() <= k) return views;
  std::vector<const data::View*> out;
  for (size_t i = 0; i < k; ++i) out.push_back(views[i * (views.size() - 1) / (k - 1)]);
  return out;
}

nlohmann::json scores_json(const Evaluation& e) {
  nlohmann::json views = nlohmann::json::array();
  for (const ViewScore& s : e.views) views.push_back({{"name", s.name}, {"time", s.time}, {"psnr", s.psnr}, {"ssim", s.ssim}});
  return views;
}

// The bounds of a cloud's means (4DGaussians sets the field's AABB from the initial points).
std::pair<std::array<float, 3>, std::array<float, 3>> bounds(const std::vector<float>& means) {
  std::array<float, 3> lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
  for (size_t i = 0; i < means.size(); ++i) lo[i % 3] = std::min(lo[i % 3], means[i]), hi[i % 3] = std::max(hi[i % 3], means[i]);
  return {lo, hi};
}

// What a resumed run continues from: its newest checkpoint, or the previous one when the newest is
// missing or damaged (read_checkpoint_or_previous). A run with neither continues from the start
// only when it holds no results either: it was killed before its first checkpoint, so nothing is
// lost (its loss.csv rows up to then are logged again). One with results (a deleted checkpoint) is
// refused before anything is loaded or written: training it again would overwrite them.
std::optional<LoadedCheckpoint> checkpoint_to_resume(const RunDir& run) {
  if (fs::exists(run.checkpoint()) || fs::exists(run.previous_checkpoint()))
    return read_checkpoint_or_previous(run.checkpoint(), run.previous_checkpoint());
  std::string results;
  auto found = [&](const fs::path& p, const char* name) {
    std::error_code ec;
    if (fs::exists(p) && !(fs::is_directory(p) && fs::is_empty(p, ec))) results += (results.empty() ? "" : ", ") + std::string(name);
  };
  found(run.train_json(), "train.json");
  found(run.gaussians_ply(), "geometry/gaussians.ply");
  found(run.eval_dir(), "eval/");
  found(run.style_dir(), "style/");
  if (!results.empty())
    throw std::runtime_error(run.checkpoint().string() + ": missing, and so is " + run.previous_checkpoint().string() +
                             "; " + run.root.string() + " holds results (" + results +
                             ") that training it again from the start would overwrite, so it is not resumed (train a "
                             "new run with --out, or delete " + run.root.string() + " to train this one again)");
  std::cerr << run.root.string() << ": no checkpoint yet (the run stopped before its first) and no results to lose; "
            << "training it from the start\n";
  return std::nullopt;
}

engine::Buffer zeros(engine::Context& ctx, const std::string& name, size_t floats) {
  engine::Buffer b(ctx, name, floats * 4);
  engine::Recorder rec(ctx, "zero " + name);
  rec.fill(b, 0);
  ctx.run(std::move(rec));
  return b;
}

}  // namespace

struct Trainer::Impl {
  engine::Context& ctx;
  RunDir run;
  const TrainConfig& config;
  const data::Dataset& dataset;
  double lr_scale;
  std::vector<const data::View*> train_views, test_views;
  std::vector<const data::View*> static_views;  // the static stage's: train views with time <= static_max_time
  data::FrameCache frames;
  std::unique_ptr<model::TrainableGaussians> gaussians;
  splat::Rasterizer rast;
  optim::ImageLoss loss;
  optim::Adam adam;
  densify::Densifier densifier;
  Evaluator evaluator;
  ViewSampler sampler;
  engine::Buffer target, v_rgb;

  // Stage 2 state: the field, its Adam moments, the deformed Gaussians and a batch's scratch.
  std::unique_ptr<deform::DeformationField> field;
  std::array<float, 3> aabb_min{}, aabb_max{};
  engine::Buffer planes_m, planes_v, mlp_m, mlp_v;
  std::array<engine::Buffer, model::kAttrCount> deformed, scratch_grad;
  engine::Buffer batch_stats;
  uint32_t sized_for = UINT32_MAX;  // Gaussian count the stage-2 buffers hold
  // The last static_count Gaussians do not move and skip the field (config.static_motion); 0 until
  // measured and again after densification.
  uint32_t static_count = 0;
  double deform_evaluations = 0, deform_evaluations_unmasked = 0;  // Gaussians the field evaluated / would have

  std::string stage = "static";
  uint32_t iteration = 0;  // within the stage
  double seconds_before = 0;
  uint32_t rollbacks = 0;
  nlohmann::json static_scores;  // the static stage's final test, once done
  nlohmann::json facts;          // the data's layout, background, initialisation and recipe (dataset_facts)
  Checkpoint last_good;          // the last state known finite: what a non-finite step rolls back to
  // Resumed from the previous checkpoint because the newest was damaged: the next checkpoint replaces
  // the newest without rotating it over the good previous one.
  bool newest_damaged = false;

  Impl(engine::Context& c, RunDir r, const TrainConfig& cfg, const data::Dataset& d)
      : ctx(c), run(std::move(r)), config(cfg), dataset(d), lr_scale(cfg.lr_scale), train_views(select_views(d, cfg, false)),
        test_views(select_views(d, cfg, true)), frames(d, kFrameCacheBytes), rast(c, "training rasterizer"),
        loss(c, "training loss"), adam(c, gCount, "training adam"), densifier(c), evaluator(c),
        sampler(1, cfg.seed) {
    for (const data::View* v : train_views)
      if (v->time <= cfg.static_max_time + 1e-9) static_views.push_back(v);
    sampler = stage_sampler();
    if (static_views.empty())
      throw std::runtime_error(d.root.string() + ": no training views with time <= " +
                               std::to_string(std::min(cfg.max_time, cfg.static_max_time)) + " for the static stage");
    if (test_views.empty()) test_views = spread(train_views, kPeriodicTestViews);  // no held-out camera: report on training views
  }

  bool fine() const { return stage == "fine"; }
  // Each stage draws from its own views, with its own seeded order.
  ViewSampler stage_sampler() const {
    const size_t views = fine() ? train_views.size() : static_views.size();
    return ViewSampler(static_cast<uint32_t>(std::max<size_t>(views, 1)), config.seed + (fine() ? 1u : 0u));
  }
  uint32_t stage_iterations() const { return fine() ? config.fine_iterations : config.iterations; }
  int active_degree() const {
    return active_sh_degree(config, fine() ? config.iterations + iteration : iteration);  // not reset (3.3)
  }

  // The field, sized from the initial cloud's bounds (validated here, so a field the device cannot
  // run fails before any training).
  void make_field(uint32_t seed) {
    if (config.fine_iterations == 0) return;
    try {
      field = std::make_unique<deform::DeformationField>(ctx, field_config(config, aabb_min, aabb_max), seed, "deformation field");
    } catch (const std::runtime_error& e) {
      throw std::runtime_error(std::string(e.what()) + " (the 4DGS stage of preset '" + config.preset +
                               "'; --preset fast fits lavapipe, --stage static trains without it)");
    }
    planes_m = zeros(ctx, "field planes adam m", field->plane_floats());
    planes_v = zeros(ctx, "field planes adam v", field->plane_floats());
    mlp_m = zeros(ctx, "field mlp adam m", field->mlp_floats());
    mlp_v = zeros(ctx, "field mlp adam v", field->mlp_floats());
  }

  nlohmann::json meta(double seconds) const {
    return {{"stage", stage},         {"iteration", iteration},   {"lr_scale", lr_scale},   {"seconds", seconds},
            {"rollbacks", rollbacks}, {"sampler", sampler.save()}, {"aabb_min", aabb_min}, {"aabb_max", aabb_max},
            {"static_test", static_scores}, {"deform_evaluations", deform_evaluations},
            {"deform_evaluations_unmasked", deform_evaluations_unmasked}};
  }

  Checkpoint snapshot(double seconds) const {
    Checkpoint cp{meta(seconds), gaussians->download(), {}};
    if (field) {
      cp.extra = {{"field.planes", field->download_planes()},
                  {"field.mlp", field->download_mlp()},
                  {"field.planes.adam_m", ctx.download<float>(planes_m, field->plane_floats())},
                  {"field.planes.adam_v", ctx.download<float>(planes_v, field->plane_floats())},
                  {"field.mlp.adam_m", ctx.download<float>(mlp_m, field->mlp_floats())},
                  {"field.mlp.adam_v", ctx.download<float>(mlp_v, field->mlp_floats())}};
      if (static_count > 0) {
        const std::vector<uint32_t> mask = deform::tail_mask(gaussians->size(), static_count);
        cp.extra.emplace_back("field.static_mask", std::vector<float>(mask.begin(), mask.end()));
      }
    }
    return cp;
  }

  void restore(const Checkpoint& cp) {
    gaussians = std::make_unique<model::TrainableGaussians>(ctx, cp.state, "gaussians");
    sized_for = UINT32_MAX;
    stage = cp.meta.at("stage").get<std::string>();
    iteration = cp.meta.at("iteration").get<uint32_t>();
    lr_scale = cp.meta.at("lr_scale").get<double>();
    seconds_before = cp.meta.at("seconds").get<double>();
    rollbacks = cp.meta.at("rollbacks").get<uint32_t>();
    sampler = stage_sampler();
    sampler.load(cp.meta.at("sampler").get<std::string>());
    static_scores = cp.meta.at("static_test");
    deform_evaluations = cp.meta.at("deform_evaluations").get<double>();
    deform_evaluations_unmasked = cp.meta.at("deform_evaluations_unmasked").get<double>();
    static_count = 0;
    if (!field) {
      aabb_min = cp.meta.at("aabb_min").get<std::array<float, 3>>();
      aabb_max = cp.meta.at("aabb_max").get<std::array<float, 3>>();
      make_field(config.seed);
    }
    if (!field) return;
    auto extra = [&](const std::string& name) -> const std::vector<float>& {
      for (const auto& [n, v] : cp.extra)
        if (n == name) return v;
      throw std::runtime_error("checkpoint: the run trains a deformation field but the array '" + name + "' is missing");
    };
    field->upload_planes(extra("field.planes"));
    field->upload_mlp(extra("field.mlp"));
    for (auto [buffer, name] : {std::pair{&planes_m, "field.planes.adam_m"}, {&planes_v, "field.planes.adam_v"},
                                {&mlp_m, "field.mlp.adam_m"}, {&mlp_v, "field.mlp.adam_v"}}) {
      const std::vector<float>& v = extra(name);
      if (v.size() * 4 != buffer->size()) throw std::runtime_error(std::string("checkpoint: array '") + name + "' has the wrong size");
      ctx.upload(*buffer, std::span<const float>(v));
    }
    for (const auto& [name, values] : cp.extra) {
      if (name != "field.static_mask") continue;
      if (values.size() != gaussians->size())
        throw std::runtime_error("checkpoint: field.static_mask holds " + std::to_string(values.size()) + " entries for " +
                                 std::to_string(gaussians->size()) + " Gaussians");
      apply_mask(std::vector<uint32_t>(values.begin(), values.end()));  // checkpoints since the split: already in order
    }
  }

  // Moves the Gaussians `mask` marks static to the end of memory, every per-Gaussian array with
  // them, so that the field runs over the moving prefix only.
  void apply_mask(const std::vector<uint32_t>& mask) {
    const deform::StaticSplit split = deform::split_static(mask);
    if (!split.identity())
      gaussians = std::make_unique<model::TrainableGaussians>(ctx, gather_state(gaussians->download(), split.order), "gaussians");
    static_count = split.static_count;
  }

  // Marks the Gaussians whose mean moves less than static_motion x extent between any two of
  // motion_samples times as static (ALGORITHMS.md has no such step: it is this project's "deform
  // only what moves").
  void update_mask() {
    const uint32_t n = gaussians->size();
    static_count = 0;  // measure with every Gaussian deformed
    std::vector<float> lo(size_t{n} * 3, INFINITY), hi(size_t{n} * 3, -INFINITY);
    const uint32_t samples = std::max<uint32_t>(2, config.motion_samples);
    for (uint32_t k = 0; k < samples; ++k) {
      const splat::GaussianParams p = deform_to(double(k) / (samples - 1));
      const std::vector<float> means = ctx.download<float>(*p.means, size_t{n} * 3);
      for (size_t i = 0; i < means.size(); ++i) lo[i] = std::min(lo[i], means[i]), hi[i] = std::max(hi[i], means[i]);
    }
    const double limit = config.static_motion * dataset.extent;
    std::vector<uint32_t> mask(n);
    for (uint32_t i = 0; i < n; ++i) {
      const double dx = hi[i * 3] - lo[i * 3], dy = hi[i * 3 + 1] - lo[i * 3 + 1], dz = hi[i * 3 + 2] - lo[i * 3 + 2];
      mask[i] = std::sqrt(dx * dx + dy * dy + dz * dz) < limit ? 1u : 0u;
    }
    apply_mask(mask);
  }

  bool mask_due() const {
    return fine() && config.static_motion > 0 && head(S4D_DEFORM_HEAD_POS) && iteration >= config.fine_densify_until &&
           (iteration - config.fine_densify_until) % std::max<uint32_t>(1, config.motion_every) == 0;
  }

  void set_learning_rates(uint32_t step) {
    const double e = dataset.extent;
    const uint32_t span = stage_iterations();
    const optim::LogLinearSchedule means{config.means_lr * e, config.means_lr_final * e, span};
    const optim::LogLinearSchedule planes{config.grid_lr * e, config.grid_lr_final * e, span};
    const optim::LogLinearSchedule mlp{config.deform_lr * e, config.deform_lr_final * e, span};
    const double lrs[gCount] = {means.at(step),   config.scaling_lr, config.rotation_lr, config.opacity_lr,
                                config.sh_dc_lr,  config.sh_rest_lr, planes.at(step),    mlp.at(step)};
    for (uint32_t g = 0; g < gCount; ++g) adam.set_group(g, {.lr = lrs[g] * lr_scale}, step);
    adam.upload();
  }

  // Uploads a view's target image; returns its camera.
  splat::Camera load_target(const data::View& view) {
    const io::ImageF& image = frames.get(view);
    const splat::Camera cam = splat::to_splat_camera(view.camera);
    const size_t n = size_t{cam.width} * cam.height * 3;
    if (target.size() < n * 4) {
      target = engine::Buffer(ctx, "training target", n * 4);
      v_rgb = engine::Buffer(ctx, "training image gradient", n * 4);
    }
    ctx.upload(target, std::span<const float>(image.data));
    return cam;
  }

  optim::LossValue record_loss(const splat::Camera& cam, float ssim_weight) {
    engine::Recorder rec(ctx, "training loss");
    loss.record(rec, rast.rgb(), target, cam.width, cam.height, 3, ssim_weight, v_rgb);
    ctx.run(std::move(rec));
    return loss.value();
  }

  void record_adam(engine::Recorder& rec) {
    model::TrainableGaussians& g = *gaussians;
    const uint32_t count = g.size();
    for (uint32_t a = model::kMeans; a < model::kSh; ++a) {
      const auto attr = model::Attr(a);
      adam.record(rec, a, g.param(attr), g.grad(attr), g.moment1(attr), g.moment2(attr), count * g.width(attr));
    }
    adam.record_rows(rec, gShDc, gShRest, g.width(model::kSh), 3, g.param(model::kSh), g.grad(model::kSh),
                     g.moment1(model::kSh), g.moment2(model::kSh), count * g.width(model::kSh));
    if (fine()) {
      adam.record(rec, gPlanes, field->planes(), field->v_planes(), planes_m, planes_v, field->plane_floats());
      adam.record(rec, gMlp, field->mlp(), field->v_mlp(), mlp_m, mlp_v, field->mlp_floats());
    }
  }

  // Stage 1: one view, the canonical Gaussians as they are. Returns the loss (maybe non-finite).
  optim::LossValue static_step() {
    const splat::Camera cam = load_target(*static_views[sampler.next()]);
    const splat::GaussianParams params = gaussians->params(active_degree());
    rast.forward(params, cam, dataset.background);
    const optim::LossValue value = record_loss(cam, config.ssim_weight);
    if (!std::isfinite(value.loss)) return value;
    rast.backward(params, {.v_rgb = &v_rgb}, gaussians->grads());
    set_learning_rates(iteration);
    engine::Recorder rec(ctx, "training update");
    if (iteration < config.densify_until) densifier.record_accumulate(rec, *gaussians, rast);
    record_adam(rec);
    ctx.run(std::move(rec));
    return value;
  }

  bool head(uint32_t bit) const { return (config.field_heads & bit) != 0; }

  void size_stage2_buffers() {
    const uint32_t n = gaussians->size();
    if (sized_for == n) return;
    for (uint32_t a = 0; a < model::kAttrCount; ++a) {
      const size_t bytes = size_t{n} * gaussians->width(model::Attr(a)) * 4;
      deformed[a] = engine::Buffer(ctx, std::string("deformed ") + model::attr_name(model::Attr(a)), bytes);
      scratch_grad[a] = engine::Buffer(ctx, std::string("batch gradient ") + model::attr_name(model::Attr(a)), bytes);
    }
    batch_stats = densifier.make_batch_scratch(n);
    sized_for = n;
  }

  deform::CanonicalGaussians canonical() const {
    const model::TrainableGaussians& g = *gaussians;
    return {.means = &g.param(model::kMeans),
            .log_scales = &g.param(model::kLogScales),
            .quats = &g.param(model::kQuats),
            .opacity_logits = &g.param(model::kOpacity),
            .sh = &g.param(model::kSh),
            .count = g.size(),
            .static_count = static_count,
            .sh_coeffs = g.sh_coeffs()};
  }

  // Deforms the canonical Gaussians to `time` and returns the rasterizer's view of the result.
  splat::GaussianParams deform_to(double time) {
    size_stage2_buffers();
    const uint32_t n = gaussians->size();
    deform_evaluations += n - static_count;
    deform_evaluations_unmasked += n;
    const uint32_t bits[model::kAttrCount] = {S4D_DEFORM_HEAD_POS, S4D_DEFORM_HEAD_SCALES, S4D_DEFORM_HEAD_ROTATIONS,
                                              S4D_DEFORM_HEAD_OPACITY, S4D_DEFORM_HEAD_SH};
    auto out = [&](model::Attr a) { return head(bits[a]) ? &deformed[a] : nullptr; };
    engine::Recorder rec(ctx, "deform");
    field->record_forward(rec, canonical(), static_cast<float>(time),
                          {out(model::kMeans), out(model::kLogScales), out(model::kQuats), out(model::kOpacity), out(model::kSh)});
    ctx.run(std::move(rec));
    splat::GaussianParams p = gaussians->params(active_degree());
    auto use = [&](model::Attr a, const engine::Buffer*& slot) { if (head(bits[a])) slot = &deformed[a]; };
    use(model::kMeans, p.means);
    use(model::kLogScales, p.log_scales);
    use(model::kQuats, p.quats);
    use(model::kOpacity, p.opacity_logits);
    use(model::kSh, p.sh);
    return p;
  }

  // The fine stage's next view. With fine_time_ramp > 0 the time window opens from the first frame
  // to the last over that fraction of the stage, so the field learns motion frame by frame: a large
  // move (a box sliding further than its size between distant times) is found by small steps,
  // which photometric gradients can follow. With `front`, the view comes from the window's newest
  // fine_time_front of time. Views outside are skipped in the sampler's order, so the choice stays
  // deterministic and resumable.
  const data::View& next_fine_view(bool front) {
    const double ramp = config.fine_time_ramp * config.fine_iterations;
    const double window = ramp > 0 ? std::min(1.0, double(iteration) / ramp) : 1.0;
    const double from = front && window < 1.0 ? window - config.fine_time_front : -1.0;
    // A band holding no view (times sparser than the band) falls back to the whole window.
    for (size_t draws = 0;; ++draws) {
      const data::View& v = *train_views[sampler.next()];
      const bool open = v.time <= window + 1e-9 || v.time <= static_window();
      if (open && (v.time >= from - 1e-9 || draws > 4 * train_views.size())) return v;
    }
  }
  double static_window() const { return std::min(config.max_time, config.static_max_time); }

  // Stage 2: a batch of views, each deformed to its time; gradients summed over the batch.
  optim::LossValue fine_step() {
    const uint32_t batch = std::max<uint32_t>(1, config.fine_batch);
    {
      engine::Recorder rec(ctx, "zero field gradients");
      field->record_zero_grads(rec);
      ctx.run(std::move(rec));
    }
    optim::LossValue mean{};
    const bool stats = iteration < config.fine_densify_until;
    for (uint32_t b = 0; b < batch; ++b) {
      const data::View& view = next_fine_view(config.fine_time_front > 0 && (iteration * batch + b) % 2 == 0);
      const splat::Camera cam = load_target(view);
      const splat::GaussianParams params = deform_to(view.time);
      rast.forward(params, cam, dataset.background);
      const optim::LossValue value = record_loss(cam, config.fine_ssim_weight);
      if (!std::isfinite(value.loss)) return value;
      mean.loss += value.loss / batch, mean.l1 += value.l1 / batch, mean.ssim += value.ssim / batch;
      // The first view's gradients land in the cloud's gradient buffers, later ones are added to them.
      splat::GaussianGrads grads = gaussians->grads();
      if (b > 0)
        grads = {&scratch_grad[model::kMeans], &scratch_grad[model::kLogScales], &scratch_grad[model::kQuats],
                 &scratch_grad[model::kOpacity], &scratch_grad[model::kSh], nullptr};
      rast.backward(params, {.v_rgb = &v_rgb}, grads);
      engine::Recorder rec(ctx, "field backward");
      field->record_backward(rec, canonical(), static_cast<float>(view.time),
                             {grads.v_means, head(S4D_DEFORM_HEAD_SCALES) ? grads.v_log_scales : nullptr,
                              head(S4D_DEFORM_HEAD_ROTATIONS) ? grads.v_quats : nullptr,
                              head(S4D_DEFORM_HEAD_OPACITY) ? grads.v_opacity_logits : nullptr,
                              head(S4D_DEFORM_HEAD_SH) ? grads.v_sh : nullptr});
      if (stats) densifier.record_accumulate_batch_add(rec, *gaussians, rast, batch_stats);
      rec.barrier();
      if (b > 0)
        for (uint32_t a = 0; a < model::kAttrCount; ++a)
          optim::record_grad_add(rec, gaussians->grad(model::Attr(a)), scratch_grad[a],
                                 gaussians->size() * gaussians->width(model::Attr(a)));
      ctx.run(std::move(rec));
    }
    set_learning_rates(iteration);
    engine::Recorder rec(ctx, "fine update");
    // The batch's loss is a sum of per-view means, so the regularisers weigh `batch` times as much
    // to keep 4DGaussians' ratio (it averages over the batch).
    const float w = static_cast<float>(batch);
    field->record_regularisers(rec, {config.plane_tv_weight * w, config.time_smoothness_weight * w,
                                     config.l1_time_planes_weight * w});
    if (stats) densifier.record_accumulate_batch_end(rec, *gaussians, batch_stats);
    rec.barrier();
    record_adam(rec);
    ctx.run(std::move(rec));
    return mean;
  }

  void densify_if_due() {
    const uint32_t it = iteration;
    const uint32_t until = fine() ? config.fine_densify_until : config.densify_until;
    if (it >= until) return;
    if (it > config.densify_from && it % config.densify_every == 0) {
      densify::DensifyRules rules;
      // A batch's statistic is the norm of a sum over its views where 4DGaussians sums gradients of
      // the batch mean: the same test is `batch` times the threshold.
      rules.grad_threshold = config.grad_threshold * (fine() ? static_cast<float>(std::max<uint32_t>(1, config.fine_batch)) : 1.0f);
      rules.dense_scale = static_cast<float>(config.percent_dense * dataset.extent);
      rules.min_opacity = config.min_opacity;
      if (!fine() && it > config.opacity_reset_every) {  // graphdeco: size pruning only after the first reset
        rules.max_screen_radius = config.max_screen_radius;
        rules.max_world_scale = static_cast<float>(0.1 * dataset.extent);
      }
      rules.budget = config.budget;
      rules.seed = config.seed * 1000003u + it + (fine() ? 0x9E3779B9u : 0u);
      densifier.densify(*gaussians, rules);
      static_count = 0;  // the Gaussians moved in memory: the split is measured again when due
    }
    // 4DGaussians' DyNeRF setting never resets opacities in the fine stage (interval 60000).
    if (!fine() && it % config.opacity_reset_every == 0) densifier.reset_opacity(*gaussians);
  }

  // loss.csv keeps the rows up to the state training continues from: a resumed run drops the rows
  // logged after its checkpoint (they are logged again), and a new run starts with the header.
  void trim_loss_log() const {
    std::string kept = "stage,iteration,loss,l1,ssim,gaussians,seconds\n", line;
    std::ifstream in(run.loss_csv());
    std::getline(in, line);  // header
    while (std::getline(in, line)) {
      const size_t comma = line.find(',');
      if (comma == std::string::npos) break;  // a row cut short by a kill
      const std::string row_stage = line.substr(0, comma);
      const uint32_t row_iteration = static_cast<uint32_t>(std::strtoul(line.c_str() + comma + 1, nullptr, 10));
      const bool before = row_stage == stage ? row_iteration <= iteration : row_stage == "static";
      if (before && std::count(line.begin(), line.end(), ',') == 6) kept += line + "\n";
    }
    util::write_file_atomic(run.loss_csv(), kept);
  }

  double elapsed(const std::chrono::steady_clock::time_point& start) const {
    return seconds_before + std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }

  // Saves the current state as the checkpoint and the PLY, or rolls back when it is not finite.
  bool checkpoint(double seconds) {
    Checkpoint cp = snapshot(seconds);
    try {
      write_checkpoint_rotating(run.checkpoint(), run.previous_checkpoint(), cp, !newest_damaged);
    } catch (const std::invalid_argument& e) {  // non-finite parameters: never written
      rollback(e.what());
      return false;
    }
    newest_damaged = false;
    io::write_ply_gaussians(run.gaussians_ply(), cp.state.cloud);
    last_good = std::move(cp);
    return true;
  }

  void rollback(const std::string& why) {
    if (++rollbacks > kMaxRollbacks)
      throw std::runtime_error("training diverged " + std::to_string(rollbacks) + " times (" + why +
                               "); the last good state is in " + run.checkpoint().string());
    const double seconds = last_good.meta.at("seconds").get<double>();
    const uint32_t rollbacks_now = rollbacks;
    const double scale = lr_scale * 0.5;
    restore(last_good);
    rollbacks = rollbacks_now;
    seconds_before = seconds;
    lr_scale = scale;
    std::cerr << stage << ": " << why << "; rolled back to iteration " << iteration
              << " and halved the learning rates (scale " << lr_scale << ")\n";
  }

  Evaluation evaluate(const std::vector<const data::View*>& views, const fs::path& save_dir = {}) {
    if (!fine())
      return evaluator.evaluate(rast, [&](const data::View&) { return gaussians->params(active_degree()); }, views, frames,
                                dataset.background, save_dir);
    return evaluator.evaluate(rast, [&](const data::View& v) { return deform_to(v.time); }, views, frames,
                              dataset.background, save_dir);
  }

  // The static stage is complete: keep its scores and move on to the fine stage (4DGaussians calls
  // training_setup again: fresh Adam moments, statistics and schedules).
  void begin_fine_stage(const Evaluation& static_test) {
    static_scores = {{"test_psnr", static_test.psnr}, {"test_ssim", static_test.ssim}, {"test_views", scores_json(static_test)}};
    stage = "fine";
    iteration = 0;
    sampler = stage_sampler();
    engine::Recorder rec(ctx, "fresh optimizer");
    for (uint32_t a = 0; a < model::kAttrCount; ++a) {
      rec.fill(gaussians->moment1(model::Attr(a)), 0);
      rec.fill(gaussians->moment2(model::Attr(a)), 0);
    }
    for (uint32_t s = 0; s < model::kStatCount; ++s) rec.fill(gaussians->stat(model::Stat(s)), 0);
    ctx.run(std::move(rec));
  }

  void write_result(const TrainResult& r) const {
    nlohmann::json j = {{"stage", r.stage},
                        {"complete", r.complete},
                        {"iteration", r.iteration},
                        {"test_psnr", r.test.psnr},
                        {"test_ssim", r.test.ssim},
                        {"seconds", r.seconds},
                        {"num_gaussians", r.num_gaussians},
                        {"rollbacks", r.rollbacks},
                        {"test_views", scores_json(r.test)},
                        {"static", static_scores},
                        {"deform_evaluations", deform_evaluations},
                        {"deform_evaluations_unmasked", deform_evaluations_unmasked},
                        {"moving_gaussians", gaussians->size() - static_count},
                        {"device", ctx.info().name},
                        {"device_peak_mib", static_cast<double>(ctx.memory_peak()) / (1 << 20)},  // this session's
                        {"data", fs::absolute(dataset.root).string()},
                        {"dataset", facts},
                        {"settings", to_json(config)}};
    util::write_file_atomic(run.train_json(), j.dump(2) + "\n");
  }

  TrainResult result(bool complete, double seconds, Evaluation test) const {
    return {complete, stage, iteration, gaussians->size(), seconds, rollbacks, std::move(test)};
  }
};

Trainer::Trainer(engine::Context& ctx, const fs::path& data_dir, const TrainConfig& config, const fs::path& run_dir)
    : config_(config) {
  validate(config_, "training settings");
  // The folder's .lock is the caller's run lock (run_lock.h), taken before the run is created.
  if (fs::exists(run_dir) && !(fs::is_directory(run_dir) && empty_but_for_lock(run_dir)))
    throw std::invalid_argument(run_dir.string() + " already exists and is not empty; continue it with --resume or choose "
                                "another --out");
  dataset_ = data::load_dataset(data_dir, load_options(config_, false));
  config_.background = dataset_.background;
  if (!dataset_.background_conflict.empty())
    std::cerr << "warning: " << dataset_.root.string() << ": background: " << dataset_.background_conflict << "\n";
  const nlohmann::json recipe = adapt_to_data(config_, dataset_);
  InitReport init;
  const io::GaussianCloud initial = initial_cloud(dataset_, config_.sh_degree, config_.random_init_points,
                                                  max_initial_points(config_), config_.seed, &init);
  impl_ = std::make_unique<Impl>(ctx, RunDir{run_dir}, config_, dataset_);
  impl_->facts = dataset_facts(dataset_, init, recipe);
  std::tie(impl_->aabb_min, impl_->aabb_max) = bounds(initial.means);
  impl_->make_field(config_.seed);  // before anything is written: a field the device cannot run fails here
  fs::create_directories(run_dir / "checkpoint");
  fs::create_directories(run_dir / "geometry");
  // "stage" names what the run's geometry is, for readers of a run (render, viewer).
  util::write_file_atomic(impl_->run.run_json(),
                          nlohmann::json{{"data", fs::absolute(data_dir).string()},
                                         {"stage", config_.fine_iterations > 0 ? "4dgs" : "static"},
                                         {"dataset", impl_->facts},
                                         {"settings", to_json(config_)}}.dump(2) + "\n");
  impl_->gaussians = std::make_unique<model::TrainableGaussians>(ctx, initial, "gaussians");
  impl_->last_good = impl_->snapshot(0);
}

Trainer::Trainer(engine::Context& ctx, const RunDir& run, const nlohmann::json& run_json) {
  const std::string where = run.run_json().string();
  if (!run_json.is_object())
    throw std::runtime_error(where + ": expected a JSON object with 'data' and 'settings', got a JSON " +
                             std::string(run_json.type_name()));
  if (!run_json.contains("data") || !run_json["data"].is_string())
    throw std::runtime_error(where + ": field 'data' (the dataset path) is missing or not a string");
  if (!run_json.contains("settings")) throw std::runtime_error(where + ": field 'settings' (the training settings) is missing");
  config_ = config_from_json(run_json["settings"], where);  // validated: a hand-edited value is refused by name
  std::optional<LoadedCheckpoint> from = checkpoint_to_resume(run);  // before anything is loaded or written
  dataset_ = data::load_dataset(run_json["data"].get<std::string>(), load_options(config_, true));
  // Runs from before the recipe stored no resolved value; nothing is left to the data on resume.
  const nlohmann::json recipe = adapt_to_data(config_, dataset_);
  impl_ = std::make_unique<Impl>(ctx, run, config_, dataset_);
  impl_->facts = run_json.contains("dataset") ? run_json["dataset"] : dataset_facts(dataset_, {}, recipe);
  if (from) {
    try {
      impl_->restore(from->checkpoint);
    } catch (const std::exception& e) {
      throw std::runtime_error(from->path.string() + ": " + e.what());
    }
    if (!from->newest_problem.empty()) {
      impl_->newest_damaged = true;
      std::cerr << "warning: " << from->newest_problem << "; resuming from the previous checkpoint " << from->path.string()
                << " (" << impl_->stage << " stage, iteration " << impl_->iteration << ")\n";
    }
  } else {
    fs::create_directories(run.root / "checkpoint");  // as a new run has them
    fs::create_directories(run.root / "geometry");
    const io::GaussianCloud initial = initial_cloud(dataset_, config_.sh_degree, config_.random_init_points,
                                                    max_initial_points(config_), config_.seed);
    std::tie(impl_->aabb_min, impl_->aabb_max) = bounds(initial.means);
    impl_->make_field(config_.seed);
    impl_->gaussians = std::make_unique<model::TrainableGaussians>(ctx, initial, "gaussians");
  }
  impl_->last_good = impl_->snapshot(impl_->seconds_before);
}

std::unique_ptr<Trainer> Trainer::resume(engine::Context& ctx, const fs::path& run_dir) {
  const RunDir run{run_dir};
  std::ifstream in(run.run_json());
  if (!in) throw std::runtime_error(run.run_json().string() + ": missing; " + run_dir.string() + " is not a training run");
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(run.run_json().string() + ": " + e.what());
  }
  return std::unique_ptr<Trainer>(new Trainer(ctx, run, j));
}

Trainer::~Trainer() = default;

TrainResult Trainer::run(const std::atomic<bool>& stop) {
  Impl& m = *impl_;
  const auto start = std::chrono::steady_clock::now();
  m.trim_loss_log();
  std::ofstream log(m.run.loss_csv(), std::ios::app);
  double probe_start = 0;
  while (true) {
    util::Progress progress(m.stage, m.stage_iterations());
    double test_psnr = NAN;
    while (m.iteration < m.stage_iterations()) {
      if (stop.load()) {
        m.checkpoint(m.elapsed(start));
        TrainResult r = m.result(false, m.elapsed(start), {});
        m.write_result(r);
        std::cerr << m.stage << ": interrupted at iteration " << m.iteration << "; checkpoint written, continue with "
                     "style4d train --resume " << m.run.root.string() << "\n";
        return r;
      }
      ++m.iteration;
      const optim::LossValue value = m.fine() ? m.fine_step() : m.static_step();
      if (!std::isfinite(value.loss)) {
        m.rollback("the loss became non-finite at iteration " + std::to_string(m.iteration));
        continue;
      }
      if (m.iteration % 10 == 0)
        log << m.stage << ',' << m.iteration << ',' << value.loss << ',' << value.l1 << ',' << value.ssim << ','
            << m.gaussians->size() << ',' << m.elapsed(start) << std::endl;  // on disk before any later checkpoint
      if (m.iteration % config_.test_every == 0 && m.iteration < m.stage_iterations())
        test_psnr = m.evaluate(spread(m.test_views, kPeriodicTestViews)).psnr;
      m.densify_if_due();  // after the test, as graphdeco reports before it densifies or resets opacities
      if (m.mask_due()) m.update_mask();
      if (m.iteration % config_.checkpoint_every == 0 && m.iteration < m.stage_iterations()) m.checkpoint(m.elapsed(start));
      std::vector<std::pair<std::string, double>> shown = {{"loss", value.loss}, {"gaussians", m.gaussians->size()}};
      if (!std::isnan(test_psnr)) shown.emplace_back("test_psnr", test_psnr);  // after the first test
      // A fresh run tells its expected length once its first steps are timed.
      if (m.stage == "static" && m.seconds_before == 0 && m.iteration == kProbeFrom) probe_start = m.elapsed(start);
      if (m.stage == "static" && m.seconds_before == 0 && m.iteration == kProbeFrom + kProbeSteps) {
        const TimeEstimate e =
            estimate_time(config_, (m.elapsed(start) - probe_start) / kProbeSteps, static_cast<uint32_t>(m.gaussians->size()));
        std::cerr << describe(e, kProbeSteps) << " on " << m.ctx.info().name << "\n";
        m.facts["estimate"] = {{"static_seconds", e.static_seconds}, {"fine_seconds", e.fine_seconds},
                               {"static_seconds_low", e.static_seconds_low}, {"fine_seconds_low", e.fine_seconds_low},
                               {"probe_seconds_per_step", e.probe_seconds_per_step}, {"probe_gaussians", e.probe_gaussians}};
      }
      progress.update(m.iteration, shown);
    }
    const bool last = m.fine() || config_.fine_iterations == 0;
    Evaluation test = m.evaluate(m.test_views, last ? m.run.eval_dir() : fs::path{});
    progress.finish({{"test_psnr", test.psnr}, {"test_ssim", test.ssim}, {"gaussians", m.gaussians->size()}});
    if (last) {
      if (!m.checkpoint(m.elapsed(start))) throw std::runtime_error("the final state is not finite");
      TrainResult r = m.result(true, m.elapsed(start), std::move(test));
      m.write_result(r);
      return r;
    }
    m.begin_fine_stage(test);
    m.checkpoint(m.elapsed(start));
  }
}

}  // namespace s4d::train
