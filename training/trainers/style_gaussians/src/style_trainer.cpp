#include "s4d/style_gaussians/style_trainer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <random>
#include <set>
#include <span>
#include <string>
#include <vector>

#include "s4d/data/frame_cache.h"
#include "s4d/engine/buffer_from.h"
#include "s4d/model/checkpoint.h"
#include "s4d/optim/adam.h"
#include "s4d/optim/adam_tensor.h"
#include "s4d/optim/grad_mask.h"
#include "s4d/optim/image_loss.h"
#include "s4d/optim/lr_schedule.h"
#include "s4d/optim/tv_loss.h"
#include "s4d/primitives/add.h"
#include "s4d/scene/cached_scene.h"
#include "s4d/scene/styled_scene.h"
#include "s4d/style_gaussians/style_budget.h"
#include "s4d/splat/rasterizer.h"
#include "s4d/splat/scene_upload.h"
#include "s4d/train/stage_runner.h"
#include "s4d/train/trainer_core.h"
#include "s4d/train/view_sampler.h"
#include "s4d/train/view_target.h"
#include "s4d/util/atomic_file.h"
#include "s4d_style_splat.h"

namespace s4d::style_gaussians {

namespace fs = std::filesystem;

namespace {

constexpr size_t kFrameCacheBytes = size_t{512} << 20;
// A time budget's plans (style_budget.h): steps are timed from kTimeMarkAfter steps after the
// trainer starts or resumes (the first compile shaders and fill caches); the first plan comes kFirstPlanSteps later, the first
// after the MLPs join kMinPlanSteps after that, the others every tenth of the stage.
constexpr uint32_t kTimeMarkAfter = 20, kFirstPlanSteps = 30, kMinPlanSteps = 10;
constexpr size_t kGeometryCacheBytes = size_t{1} << 30;
enum Group : uint32_t { gShDc, gShRest, gOpacity, gMlp, gCount };
// The trained tensors' names, as checkpoints hold them.
const char* const kTensorNames[3] = {"sh_delta", "opacity_delta", "mlp"};

std::vector<const data::View*> views_of(const data::Dataset& d, bool test) {
  std::vector<const data::View*> out;
  for (const data::View& v : d.views)
    if (v.test == test) out.push_back(&v);
  return out;
}

// SuperGaussians' initialisation: weights U(-0.5, 0.5), biases 0; "identity" also zeroes the last
// layer, so every MLP starts by adding nothing (2 sigmoid(0) - 1 = 0, sigmoid(0) - 0.5 = 0).
std::vector<float> initial_mlp(uint32_t count, const std::string& init, uint32_t seed) {
  std::vector<float> w(size_t{count} * S4D_STYLE_MLP_STRIDE, 0.0f);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-0.5f, 0.5f);
  const uint32_t weight_end = init == "identity" ? S4D_STYLE_MLP_W3 : S4D_STYLE_MLP_B3;
  for (uint32_t i = 0; i < count; ++i) {
    float* p = &w[size_t{i} * S4D_STYLE_MLP_STRIDE];
    for (uint32_t k = 0; k < weight_end; ++k) {
      const bool bias = (k >= S4D_STYLE_MLP_B1 && k < S4D_STYLE_MLP_W2) || (k >= S4D_STYLE_MLP_B2 && k < S4D_STYLE_MLP_W3);
      p[k] = bias ? 0.0f : u(rng);
    }
  }
  return w;
}

// 1 / (3 x the median largest scale): a Gaussian's own extent maps to about one unit of input.
float automatic_depth_scale(engine::Context& ctx, const splat::GaussianParams& g) {
  std::vector<float> s = ctx.download<float>(*g[splat::Attr::log_scales], size_t{g.count} * 3), largest(g.count);
  for (uint32_t i = 0; i < g.count; ++i) largest[i] = std::exp(std::max({s[3 * i], s[3 * i + 1], s[3 * i + 2]}));
  std::nth_element(largest.begin(), largest.begin() + g.count / 2, largest.end());
  return 1.0f / (3.0f * std::max(largest[g.count / 2], 1e-6f));
}

// 1 for the Gaussians whose centre lies in the box (min xyz, max xyz), else 0.
std::vector<uint32_t> inside_region(engine::Context& ctx, const splat::GaussianParams& g, const std::vector<float>& box) {
  const std::vector<float> means = ctx.download<float>(*g[splat::Attr::means], size_t{g.count} * 3);
  std::vector<uint32_t> mask(g.count);
  for (uint32_t i = 0; i < g.count; ++i) {
    bool in = true;
    for (int a = 0; a < 3; ++a) in = in && means[3 * i + a] >= box[a] && means[3 * i + a] <= box[3 + a];
    mask[i] = in ? 1u : 0u;
  }
  return mask;
}

}  // namespace

// Stage 4 as the runner drives it; the views, frames, rasterizer, loss, Adam, evaluator and guard
// are the TrainerCore's.
struct StyleTrainer::Impl final : train::TrainerCore, train::RunnerStage {
  const scene::TrainedRun& run;
  std::string style;  // the style's name
  StyleConfig config;
  fs::path dir;
  std::unique_ptr<scene::CachedScene> geometry;
  optim::TvLoss tv;
  uint32_t count = 0, sh_coeffs = 0;
  float depth_scale = 1;
  bool full = false;
  // Trained per-Gaussian arrays and their gradients, with Adam's view of them (`adam_tensors`):
  // [0] SH deltas, [1] opacity deltas, [2] MLPs. batch_grad: a batch's later views' gradients, added
  // to grad (config.batch > 1 only).
  std::array<engine::Buffer, 3> param, grad, batch_grad;
  std::array<optim::AdamTensor, 3> adam_tensors;
  std::array<size_t, 3> floats{};
  engine::Buffer sh, opacity, v_means, v_scales, v_quats;
  splat::StyleMlp mlp_desc{};
  engine::Buffer region_mask;  // [count] u32, 1 = stylized; empty: every Gaussian
  uint32_t region_count = 0;
  uint32_t done = 0;  // steps done
  std::chrono::steady_clock::time_point start;  // of this process's run()
  double last_loss = 0;
  train::Evaluation test;  // the closing test
  // A time budget (style_budget.h): `deadline` in seconds(); the lengths are planned from `start_config`.
  double deadline = 0;
  StyleConfig start_config;
  nlohmann::json plans = nlohmann::json::array();
  uint32_t mark_iteration = 0, plans_made = 0;  // since this trainer started or resumed
  double mark_seconds = -1;  // < 0: not marked yet
  bool mark_mlp = false;     // the phase of the steps since the mark
  double plain_step = 0, mlp_ratio = kMlpStepRatio;  // measured: a colour-only step, an MLP step in them

  Impl(engine::Context& c, const scene::TrainedRun& r, const data::Dataset& stylized, std::string n, const StyleConfig& cfg,
       double stage_deadline)
      : TrainerCore(c, {.name = "style",
                        .frames_of = &stylized,
                        .train_views = views_of(stylized, false),
                        .test_views = views_of(stylized, true),
                        .frame_cache_bytes = kFrameCacheBytes,
                        .adam_groups = gCount,
                        .seed = cfg.seed,
                        .background = r.dataset.background}),
        run(r), style(std::move(n)), config(cfg), dir(run::style_dir(r.root, style)), tv(c, "style tv"),
        deadline(stage_deadline), start_config(cfg) {
    if (train_views.empty()) throw std::runtime_error(stylized.root.string() + ": no training views to stylize against");
    full = config.method == run::StyleMethod::full;
    std::set<double> times;
    for (const data::View& view : stylized.views) times.insert(view.time);
    geometry = std::make_unique<scene::CachedScene>(ctx, scene::open_scene(ctx, run, "original"),
                                                    std::vector<double>(times.begin(), times.end()), kGeometryCacheBytes);
    const splat::GaussianParams g = geometry->at(*times.begin(), {});
    if (g[splat::Attr::sh] == nullptr || g[splat::Attr::colors] != nullptr) throw std::runtime_error(run.root.string() + ": the run has no SH colours to stylize");
    count = g.count, sh_coeffs = g.sh_coeffs;
    depth_scale = config.depth_scale > 0 ? config.depth_scale : automatic_depth_scale(ctx, g);
    floats = {size_t{count} * sh_coeffs * 3, count, full ? size_t{count} * S4D_STYLE_MLP_STRIDE : 0};
    for (size_t k = 0; k < 3; ++k) {
      const std::string what = std::string("style ") + kTensorNames[k];
      param[k] = engine::zeroed_buffer(ctx, what, floats[k]);
      grad[k] = engine::zeroed_buffer(ctx, what + " grad", floats[k]);
      adam_tensors[k] = optim::AdamTensor(ctx, kTensorNames[k], param[k], &grad[k], floats[k]);
      if (config.batch > 1) batch_grad[k] = engine::zeroed_buffer(ctx, what + " batch grad", floats[k]);
    }
    std::vector<float> mlp = full ? initial_mlp(count, config.mlp_init, config.seed) : std::vector<float>{};
    region_count = count;
    if (!config.region.empty()) {
      const std::vector<uint32_t> mask = inside_region(ctx, g, config.region);
      region_count = static_cast<uint32_t>(std::count(mask.begin(), mask.end(), 1u));
      for (uint32_t i = 0; i < count && full; ++i)  // outside: an MLP of zeros adds nothing
        if (mask[i] == 0) std::fill_n(mlp.begin() + i * S4D_STYLE_MLP_STRIDE, S4D_STYLE_MLP_STRIDE, 0.0f);
      region_mask = engine::buffer_from(ctx, "style region mask", mask);
    }
    if (full) ctx.upload(param[2], std::span<const float>(mlp));
    sh = engine::Buffer(ctx, "styled sh", floats[0] * 4);
    opacity = engine::Buffer(ctx, "styled opacity", floats[1] * 4);
    v_means = engine::Buffer(ctx, "style v means (unused)", size_t{count} * 3 * 4);
    v_scales = engine::Buffer(ctx, "style v scales (unused)", size_t{count} * 3 * 4);
    v_quats = engine::Buffer(ctx, "style v quats (unused)", size_t{count} * 4 * 4);
  }

  fs::path checkpoint_path() const { return dir / "checkpoint.s4dckpt"; }

  // ---- What the runner asks of a stage (stage_runner.h).
  train::StagePlan plan() const override {
    return {.name = "stage 4",
            .progress_label = "stage 4 " + style,
            .iterations = config.iterations,
            .test_every = config.test_every,
            .checkpoint_every = config.checkpoint_every,
            .test_name = "test_psnr_vs_stylized",
            .resume_hint = "run the same style4d stylize command again to continue",
            .checkpoint = checkpoint_path()};
  }
  uint32_t iteration() const override { return done; }
  double seconds() const override {
    return seconds_before + std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  train::Recovery& recovery() override { return TrainerCore::recovery; }
  void write_loss_row(std::ostream& log, double seconds) const override { log << done << ',' << last_loss << ',' << seconds; }
  bool keeps_loss_row(const std::string& row) const override { return std::strtoul(row.c_str(), nullptr, 10) <= done; }
  double periodic_test() override { return evaluate(train::spread_views(test_views, train::kPeriodicTestViews)).psnr; }
  void save(double seconds) override {
    model::Checkpoint cp = snapshot(seconds);
    train::Divergence d = train::find_divergence(cp, {}, count);
    save_checked(std::move(cp), std::move(d), [&](const model::Checkpoint& state) { model::write_checkpoint(checkpoint_path(), state); });
  }
  void restore_last_good() override { restore(last_good); }
  train::Divergence divergence() override { return train::find_divergence(snapshot(seconds()), {}, count); }
  // The Gaussians' style deltas, MLPs and moments back to zero: an MLP of zeros adds nothing.
  std::string repair_gaussians(const std::vector<uint32_t>& rows) override {
    for (size_t k = 0; k < 3; ++k) {
      if (floats[k] == 0) continue;
      const size_t width = floats[k] / count;
      std::vector<float> values = ctx.download<float>(param[k], floats[k]);
      for (uint32_t g : rows) std::fill_n(values.begin() + g * width, width, 0.0f);
      ctx.upload(param[k], std::span<const float>(values));
      adam_tensors[k].zero_rows(rows, width);
    }
    return "reset the style of";
  }
  void after_step() override { plan_time_if_due(); }
  train::ProgressValues final_test() override {
    test = evaluate(test_views, dir / "eval");
    return {{"test_psnr_vs_stylized", test.psnr}};
  }

  nlohmann::json meta(double seconds) const {
    nlohmann::json j = {{"iteration", done}, {"seconds", seconds}, {"sampler", sampler.save()}, {"settings", to_json(config)},
                        {"count", count}, {"depth_scale", depth_scale}};
    if (TrainerCore::recovery.rollbacks > 0) {  // absent: none, so a run that never rolled back writes what it always did
      j["rollbacks"] = TrainerCore::recovery.rollbacks;
      j["lr_scale"] = TrainerCore::recovery.lr_scale;
    }
    if (TrainerCore::recovery.repairs > 0) j["guard_repairs"] = TrainerCore::recovery.repairs, j["guard_reset"] = TrainerCore::recovery.removed;
    if (!plans.empty()) j["time_budget"] = {{"start", to_json(start_config)}, {"plans", plans}};  // absent: never planned
    return j;
  }

  model::Checkpoint snapshot(double seconds) const {
    model::Checkpoint cp{meta(seconds), {}, {}};
    for (size_t k = 0; k < 3; ++k) {
      if (floats[k] == 0) continue;
      cp.extra.emplace_back(kTensorNames[k], ctx.download<float>(param[k], floats[k]));
      for (auto& moment : adam_tensors[k].download_moments(optim::MomentNames::trainer)) cp.extra.push_back(std::move(moment));
    }
    return cp;
  }

  void restore(const model::Checkpoint& cp) {
    // A planned style (time budget) started from the settings asked for and goes on with its plan's lengths.
    const bool planned = cp.meta.contains("time_budget");
    const nlohmann::json saved = planned ? cp.meta.at("time_budget").at("start") : cp.meta.at("settings");
    if (saved != to_json(start_config))
      throw std::runtime_error(checkpoint_path().string() + " was written with other settings (" + saved.dump() +
                               "); pass the same options or --restart");
    if (planned) {
      config = style_config_from_json(cp.meta.at("settings"));
      plans = cp.meta.at("time_budget").at("plans");
    }
    if (cp.meta.at("count").get<uint32_t>() != count)
      throw std::runtime_error(checkpoint_path().string() + ": trained for another Gaussian count; the run was retrained (use --restart)");
    done = cp.meta.at("iteration").get<uint32_t>();
    sampler.load(cp.meta.at("sampler").get<std::string>());
    depth_scale = cp.meta.at("depth_scale").get<float>();
    TrainerCore::recovery = {cp.meta.value("rollbacks", 0u), cp.meta.value("lr_scale", 1.0), cp.meta.value("guard_repairs", 0u),
                      cp.meta.value("guard_reset", 0u)};
    auto find = [&](const std::string& array) -> const std::vector<float>& {
      return train::checkpoint_array(cp, array, checkpoint_path().string());
    };
    for (size_t k = 0; k < 3; ++k) {
      if (floats[k] == 0) continue;
      const std::vector<float>& values = find(kTensorNames[k]);
      if (values.size() != floats[k])
        throw std::runtime_error(checkpoint_path().string() + ": array '" + kTensorNames[k] + "' is of the wrong size");
      ctx.upload(param[k], std::span<const float>(values));
      adam_tensors[k].upload_moments(optim::MomentNames::trainer, find, checkpoint_path().string());
    }
  }

  void mark_time(double now) { mark_iteration = done, mark_seconds = now, mark_mlp = mlp_phase(config, done); }

  // The stage's lengths re-fitted to the deadline from the steps timed since the mark (style_budget.h).
  void plan_time_if_due() {
    if (deadline <= 0) return;
    const double now = seconds();
    if (mark_seconds < 0) {
      if (done >= mark_iteration + kTimeMarkAfter) mark_time(now);
      return;
    }
    const bool mlp = mlp_phase(config, done);
    if (mlp != mark_mlp) return mark_time(now);  // the MLPs joined: time their steps alone
    const uint32_t steps = done - mark_iteration;
    const bool first_mlp = mlp && plain_step > 0 && !plans.empty() && plans.back().value("phase", "") != "mlp";
    const uint32_t due = plans_made == 0 ? kFirstPlanSteps : first_mlp ? kMinPlanSteps : std::max(kMinPlanSteps, config.iterations / 10);
    if (steps < due || done >= config.iterations) return;
    const double per_step = (now - mark_seconds) / steps;
    if (!mlp) plain_step = per_step;
    else if (plain_step > 0 && full && start_config.mlp_iterations < start_config.iterations) mlp_ratio = per_step / plain_step;
    const StyleLengths fitted = fitted_style_lengths(start_config, config, done, deadline, now, per_step, mlp_ratio);
    const bool changed = fitted.iterations != config.iterations;
    config.iterations = fitted.iterations, config.mlp_iterations = fitted.mlp_iterations;
    plans.push_back({{"phase", mlp ? "mlp" : "colors"}, {"iteration", done}, {"seconds", now}, {"seconds_per_step", per_step},
                     {"mlp_step_ratio", mlp_ratio}, {"iterations", config.iterations}, {"mlp_iterations", config.mlp_iterations}});
    mark_time(now);
    if (plans_made++ > 0 && !first_mlp) return;  // the later plans are in stylize.json
    if (!changed) return;
    std::fprintf(stderr, "time budget: stage 4 %u steps, the last %u with the MLPs (%.3f s per %s step at step %u; %.0f of %.0f s)\n",
                 config.iterations, config.mlp_iterations, per_step, mlp ? "MLP" : "colour", done, now, deadline);
  }

  nlohmann::json time_budget_json() const {
    if (deadline <= 0) return nullptr;
    return {{"deadline_seconds", deadline}, {"start_iterations", start_config.iterations},
            {"start_mlp_iterations", start_config.mlp_iterations}, {"plans", plans}};
  }

  // The MLPs' learning rate at step `done` (1-based), which is their step done - (iterations - mlp_iterations).
  double mlp_lr() const {
    if (config.mlp_lr_final == 0) return config.mlp_lr;
    const uint32_t first = config.iterations - config.mlp_iterations;  // steps before the MLPs join
    return optim::LogLinearSchedule{config.mlp_lr, config.mlp_lr_final, config.mlp_iterations}.at(done - 1 - first);
  }

  // The run's Gaussians at the view's time in this style (`with_mlp` false: colours only).
  splat::GaussianParams styled(const data::View& view, const splat::Camera& cam, bool with_mlp = true) {
    const splat::GaussianParams g = geometry->at(view.time, cam);
    engine::Recorder rec(ctx, "style deltas");
    const splat::GaussianParams p = record_styled(rec, view, g, with_mlp);
    ctx.run(std::move(rec));
    return p;
  }

  // Records the style's deltas on the run's Gaussians `g` at the view's time into `rec`.
  splat::GaussianParams record_styled(engine::Recorder& rec, const data::View& view, const splat::GaussianParams& g,
                                      bool with_mlp) {
    splat::GaussianParams p = scene::record_style_deltas(rec, g, param[0], param[1], sh, opacity);
    if (full && with_mlp) {
      mlp_desc = scene::style_mlp(view.time, config.depth_input, depth_scale, config.input_sigmoid);
      p.style = &mlp_desc;
      p[splat::Attr::style_mlp] = &param[2];
    }
    return p;
  }

  // One view's loss (L1 + TV) and its gradients into `out` (assigned); returns the loss.
  double view_gradients(const data::View& view, bool mlp, std::array<engine::Buffer, 3>& out) {
    const splat::Camera cam = target.load(view, frames);
    const splat::GaussianParams g = geometry->at(view.time, cam);
    splat::GaussianParams p;
    const optim::LossValue l = forward_loss(cam, config.ssim_weight, [&](engine::Recorder& rec) {
      return p = record_styled(rec, view, g, mlp);
    });
    if (config.tv_weight > 0) {
      engine::Recorder rec(ctx, "style tv");
      tv.record(rec, rast.rgb(), cam.width, cam.height, 3, config.tv_weight, target.image_gradient());
      ctx.run(std::move(rec));
    }
    const double value = l.loss + (config.tv_weight > 0 ? tv.value() : 0.0);
    if (!std::isfinite(value)) return value;
    splat::GaussianGrads grads;
    grads[splat::Attr::means] = &v_means, grads[splat::Attr::log_scales] = &v_scales, grads[splat::Attr::quats] = &v_quats;
    grads[splat::Attr::opacity_logits] = &out[1], grads[splat::Attr::sh] = &out[0];
    if (mlp) grads[splat::Attr::style_mlp] = &out[2];
    rast.backward(p, {.v_rgb = &target.image_gradient()}, grads);
    return value;
  }

  // A step over config.batch views: the first view's gradients land in grad, the later ones' are
  // added to them (summed, see StyleConfig::batch); the loss is the views' mean.
  double step() override {
    const bool mlp = mlp_phase(config, done);  // method full's last mlp_iterations steps
    ++done;
    last_loss = 0;
    for (uint32_t b = 0; b < config.batch; ++b) {
      const double value = view_gradients(*train_views[sampler.next()], mlp, b == 0 ? grad : batch_grad);
      last_loss = std::isfinite(value) ? last_loss + value / config.batch : value;
      if (!std::isfinite(last_loss)) return last_loss;
      if (b == 0) continue;
      engine::Recorder rec(ctx, "style batch gradients");
      for (size_t k = 0; k < 3; ++k)
        if (floats[k] > 0 && (k != 2 || mlp)) primitives::cmd_add(rec, grad[k], batch_grad[k], static_cast<uint32_t>(floats[k]));
      ctx.run(std::move(rec));
    }
    if (region_mask.size() > 0) {
      engine::Recorder rec(ctx, "style region");
      optim::record_grad_mask(rec, grad[0], region_mask, count, sh_coeffs * 3);
      optim::record_grad_mask(rec, grad[1], region_mask, count, 1);
      if (mlp) optim::record_grad_mask(rec, grad[2], region_mask, count, S4D_STYLE_MLP_STRIDE);
      ctx.run(std::move(rec));
    }
    const bool colors = !full || config.train_colors;
    const double lrs[gCount] = {colors ? config.sh_dc_lr : 0.0, colors ? config.sh_rest_lr : 0.0,
                                colors ? config.opacity_lr : 0.0, mlp ? mlp_lr() : 0.0};
    for (uint32_t k = 0; k < gCount; ++k) adam.set_group(k, {.lr = lrs[k] * TrainerCore::recovery.lr_scale}, done);
    adam.upload();
    engine::Recorder rec(ctx, "style update");
    if (colors) {
      adam_tensors[0].record_rows(adam, rec, gShDc, gShRest, sh_coeffs * 3, 3);
      adam_tensors[1].record(adam, rec, gOpacity);
    }
    if (mlp) adam_tensors[2].record(adam, rec, gMlp);
    ctx.run(std::move(rec));
    return last_loss;
  }

  train::Evaluation evaluate(const std::vector<const data::View*>& views, const fs::path& save_dir = {}) {
    return TrainerCore::evaluate([&](const data::View& view) { return styled(view, splat::to_splat_camera(view.camera)); },
                                 views, save_dir);
  }

  run::StyleFile style_file() const {
    run::StyleFile s;
    s.method = config.method;
    s.settings = to_json(config);
    s.count = count, s.sh_coeffs = sh_coeffs;
    s.sh_delta = ctx.download<float>(param[0], floats[0]);
    s.opacity_delta = ctx.download<float>(param[1], floats[1]);
    if (full) s.mlp = ctx.download<float>(param[2], floats[2]);
    s.depth_input = config.depth_input, s.depth_scale = depth_scale, s.input_sigmoid = config.input_sigmoid;
    return s;
  }
};

StyleTrainer::StyleTrainer(engine::Context& ctx, const scene::TrainedRun& run, const data::Dataset& stylized, std::string name,
                           const StyleConfig& config, double deadline) {
  validate(config);
  if (config.method == run::StyleMethod::scratch) throw std::invalid_argument("method scratch retrains 4DGS (style4d train), not stage 4");
  impl_ = std::make_unique<Impl>(ctx, run, stylized, std::move(name), config, deadline);
  fs::create_directories(impl_->dir);
  if (fs::exists(impl_->checkpoint_path())) {
    const model::Checkpoint cp = model::read_checkpoint(impl_->checkpoint_path());
    impl_->restore(cp);
    // Only here: a rollback within a run keeps the seconds spent.
    impl_->seconds_before = cp.meta.at("seconds").get<double>();
  }
  impl_->last_good = impl_->snapshot(impl_->seconds_before);
  impl_->mark_iteration = impl_->done;  // the first steps after a start or resume are not timed
}

StyleTrainer::~StyleTrainer() = default;

StyleResult StyleTrainer::run(const std::atomic<bool>& stop) {
  Impl& s = *impl_;
  s.start = std::chrono::steady_clock::now();
  train::StageRunner runner(s.dir / "loss.csv", "iteration,loss,seconds");
  // A refused final checkpoint was repaired (the closing test runs again) or rolled back (training goes on).
  do {
    if (!runner.run(s, stop)) return {false, s.done, s.seconds(), s.region_count, {}, s.time_budget_json()};
  } while (!runner.checkpoint(s));
  run::write_style_file(run::style_file_path(s.run.root, s.style), s.style_file());
  return {true, s.done, s.seconds(), s.region_count, std::move(s.test), s.time_budget_json()};
}

}  // namespace s4d::style_gaussians
