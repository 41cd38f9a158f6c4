#include "s4d/train/static_trainer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <iostream>
#include <sstream>
#include <stdexcept>

#include "s4d/data/frame_cache.h"
#include "s4d/densify/densifier.h"
#include "s4d/engine/buffer_from.h"
#include "s4d/io/ply_gaussians.h"
#include "s4d/model/trainable_gaussians.h"
#include "s4d/optim/adam.h"
#include "s4d/optim/image_loss.h"
#include "s4d/optim/lr_schedule.h"
#include "s4d/splat/rasterizer.h"
#include "s4d/splat/scene_upload.h"
#include "s4d/train/checkpoint.h"
#include "s4d/train/init_cloud.h"
#include "s4d/train/view_sampler.h"
#include "s4d/util/atomic_file.h"
#include "s4d/util/progress.h"

namespace s4d::train {

namespace fs = std::filesystem;

namespace {

constexpr size_t kFrameCacheBytes = size_t{1} << 30;
constexpr uint32_t kMaxRollbacks = 8;   // each halves the learning rates
constexpr size_t kPeriodicTestViews = 8;  // periodic tests use this many test views; the final one all

// Adam groups: one per attribute, and the SH rows split into DC and the rest.
enum Group : uint32_t { gMeans, gScales, gQuats, gOpacity, gShDc, gShRest, gCount };

data::LoadOptions load_options(const TrainConfig& c) {
  return {.downscale = c.downscale, .background = c.background};
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

}  // namespace

struct StaticTrainer::Impl {
  engine::Context& ctx;
  RunDir run;
  const TrainConfig& config;
  const data::Dataset& dataset;
  double lr_scale;
  std::vector<const data::View*> train_views, test_views;
  data::FrameCache frames;
  std::unique_ptr<model::TrainableGaussians> gaussians;
  splat::Rasterizer rast;
  optim::ImageLoss loss;
  optim::Adam adam;
  densify::Densifier densifier;
  Evaluator evaluator;
  ViewSampler sampler;
  engine::Buffer target, v_rgb;

  uint32_t iteration = 0;
  double seconds_before = 0;  // training time of earlier sessions
  uint32_t rollbacks = 0;
  Checkpoint last_good;  // the last state known finite: what a non-finite step rolls back to

  Impl(engine::Context& c, RunDir r, const TrainConfig& cfg, const data::Dataset& d)
      : ctx(c), run(std::move(r)), config(cfg), dataset(d), lr_scale(cfg.lr_scale), train_views(select_views(d, cfg, false)),
        test_views(select_views(d, cfg, true)), frames(d, kFrameCacheBytes), rast(c, "training rasterizer"),
        loss(c, "training loss"), adam(c, gCount, "training adam"), densifier(c), evaluator(c),
        sampler(static_cast<uint32_t>(std::max<size_t>(train_views.size(), 1)), cfg.seed) {
    if (train_views.empty())
      throw std::runtime_error(d.root.string() + ": no training views with time <= " + std::to_string(cfg.max_time));
    if (test_views.empty()) test_views = spread(train_views, kPeriodicTestViews);  // no held-out camera: report on training views
  }

  nlohmann::json meta(double seconds) const {
    return {{"stage", "static"}, {"iteration", iteration}, {"lr_scale", lr_scale}, {"seconds", seconds},
            {"rollbacks", rollbacks}, {"sampler", sampler.save()}};
  }

  void restore(const Checkpoint& cp) {
    gaussians = std::make_unique<model::TrainableGaussians>(ctx, cp.state, "gaussians");
    iteration = cp.meta.at("iteration").get<uint32_t>();
    lr_scale = cp.meta.at("lr_scale").get<double>();
    seconds_before = cp.meta.at("seconds").get<double>();
    rollbacks = cp.meta.at("rollbacks").get<uint32_t>();
    sampler.load(cp.meta.at("sampler").get<std::string>());
  }

  int active_degree() const { return std::min<int>(config.sh_degree, static_cast<int>(iteration / config.sh_up_every)); }

  void set_learning_rates(uint32_t step) {
    const optim::LogLinearSchedule means{config.means_lr * dataset.extent, config.means_lr_final * dataset.extent,
                                         config.iterations};
    const double lrs[gCount] = {means.at(step), config.scaling_lr, config.rotation_lr, config.opacity_lr, config.sh_dc_lr,
                                config.sh_rest_lr};
    for (uint32_t g = 0; g < gCount; ++g) adam.set_group(g, {.lr = lrs[g] * lr_scale}, step);
    adam.upload();
  }

  // One optimisation step on one view; returns the loss, which may be non-finite.
  optim::LossValue step() {
    const data::View& view = *train_views[sampler.next()];
    const io::ImageF& image = frames.get(view);
    const splat::Camera cam = splat::to_splat_camera(view.camera);
    const size_t n = size_t{cam.width} * cam.height * 3;
    if (target.size() < n * 4) {
      target = engine::Buffer(ctx, "training target", n * 4);
      v_rgb = engine::Buffer(ctx, "training image gradient", n * 4);
    }
    ctx.upload(target, std::span<const float>(image.data));
    const splat::GaussianParams params = gaussians->params(active_degree());
    rast.forward(params, cam, dataset.background);
    {
      engine::Recorder rec(ctx, "training loss");
      loss.record(rec, rast.rgb(), target, cam.width, cam.height, 3, config.ssim_weight, v_rgb);
      ctx.run(std::move(rec));
    }
    const optim::LossValue value = loss.value();
    if (!std::isfinite(value.loss)) return value;
    rast.backward(params, {.v_rgb = &v_rgb}, gaussians->grads());
    set_learning_rates(iteration);
    engine::Recorder rec(ctx, "training update");
    if (iteration < config.densify_until) densifier.record_accumulate(rec, *gaussians, rast);
    model::TrainableGaussians& g = *gaussians;
    const uint32_t count = g.size();
    for (uint32_t a = model::kMeans; a < model::kSh; ++a) {
      const auto attr = model::Attr(a);
      adam.record(rec, a, g.param(attr), g.grad(attr), g.moment1(attr), g.moment2(attr), count * g.width(attr));
    }
    adam.record_rows(rec, gShDc, gShRest, g.width(model::kSh), 3, g.param(model::kSh), g.grad(model::kSh),
                     g.moment1(model::kSh), g.moment2(model::kSh), count * g.width(model::kSh));
    ctx.run(std::move(rec));
    return value;
  }

  void densify_if_due() {
    const uint32_t it = iteration;
    if (it >= config.densify_until) return;
    if (it > config.densify_from && it % config.densify_every == 0) {
      densify::DensifyRules rules;
      rules.grad_threshold = config.grad_threshold;
      rules.dense_scale = static_cast<float>(config.percent_dense * dataset.extent);
      rules.min_opacity = config.min_opacity;
      if (it > config.opacity_reset_every) {  // graphdeco: size pruning only after the first opacity reset
        rules.max_screen_radius = config.max_screen_radius;
        rules.max_world_scale = static_cast<float>(0.1 * dataset.extent);
      }
      rules.budget = config.budget;
      rules.seed = config.seed * 1000003u + it;
      densifier.densify(*gaussians, rules);
    }
    if (it % config.opacity_reset_every == 0) densifier.reset_opacity(*gaussians);
  }

  double elapsed(const std::chrono::steady_clock::time_point& start) const {
    return seconds_before + std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }

  // Saves the current state as the checkpoint and the PLY, or rolls back when it is not finite.
  bool checkpoint(double seconds) {
    Checkpoint cp{meta(seconds), gaussians->download()};
    try {
      write_checkpoint(run.checkpoint(), cp);
    } catch (const std::invalid_argument& e) {  // non-finite parameters: never written
      rollback(e.what());
      return false;
    }
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
    restore(last_good);
    rollbacks = rollbacks_now;
    seconds_before = seconds;
    lr_scale *= 0.5;
    std::cerr << "static: " << why << "; rolled back to iteration " << iteration << " and halved the learning rates (scale "
              << lr_scale << ")\n";
  }

  void write_result(const TrainResult& r) const {
    nlohmann::json j = {{"stage", "static"},
                        {"complete", r.complete},
                        {"iteration", r.iteration},
                        {"test_psnr", r.test.psnr},
                        {"test_ssim", r.test.ssim},
                        {"seconds", r.seconds},
                        {"num_gaussians", r.num_gaussians},
                        {"rollbacks", r.rollbacks},
                        {"test_views", scores_json(r.test)},
                        {"device", ctx.info().name},
                        {"data", fs::absolute(dataset.root).string()},
                        {"settings", to_json(config)}};
    util::write_file_atomic(run.train_json(), j.dump(2) + "\n");
  }
};

StaticTrainer::StaticTrainer(engine::Context& ctx, const fs::path& data_dir, const TrainConfig& config, const fs::path& run_dir)
    : config_(config) {
  if (fs::exists(run_dir) && !(fs::is_directory(run_dir) && fs::is_empty(run_dir)))
    throw std::invalid_argument(run_dir.string() + " already exists and is not empty; continue it with --resume or choose "
                                "another --out");
  dataset_ = data::load_dataset(data_dir, load_options(config_));
  config_.background = dataset_.background;
  fs::create_directories(run_dir / "checkpoint");
  fs::create_directories(run_dir / "geometry");
  const RunDir run{run_dir};
  util::write_file_atomic(run.run_json(), nlohmann::json{{"data", fs::absolute(data_dir).string()},
                                                         {"stage", "static"},
                                                         {"settings", to_json(config_)}}.dump(2) + "\n");
  impl_ = std::make_unique<Impl>(ctx, run, config_, dataset_);
  impl_->gaussians = std::make_unique<model::TrainableGaussians>(
      ctx, initial_cloud(dataset_, config_.sh_degree, config_.random_init_points, config_.seed), "gaussians");
  impl_->last_good = {impl_->meta(0), impl_->gaussians->download()};
}

StaticTrainer::StaticTrainer(engine::Context& ctx, const RunDir& run, const nlohmann::json& run_json) {
  try {
    config_ = config_from_json(run_json.at("settings"));
    dataset_ = data::load_dataset(run_json.at("data").get<std::string>(), load_options(config_));
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(run.run_json().string() + ": " + e.what());
  }
  impl_ = std::make_unique<Impl>(ctx, run, config_, dataset_);
  if (fs::exists(run.checkpoint())) {
    impl_->restore(read_checkpoint(run.checkpoint()));
  } else {
    impl_->gaussians = std::make_unique<model::TrainableGaussians>(
        ctx, initial_cloud(dataset_, config_.sh_degree, config_.random_init_points, config_.seed), "gaussians");
  }
  impl_->last_good = {impl_->meta(impl_->seconds_before), impl_->gaussians->download()};
}

std::unique_ptr<StaticTrainer> StaticTrainer::resume(engine::Context& ctx, const fs::path& run_dir) {
  const RunDir run{run_dir};
  std::ifstream in(run.run_json());
  if (!in) throw std::runtime_error(run.run_json().string() + ": missing; " + run_dir.string() + " is not a training run");
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(run.run_json().string() + ": " + e.what());
  }
  return std::unique_ptr<StaticTrainer>(new StaticTrainer(ctx, run, j));
}

StaticTrainer::~StaticTrainer() = default;

TrainResult StaticTrainer::run(const std::atomic<bool>& stop) {
  Impl& m = *impl_;
  const auto start = std::chrono::steady_clock::now();
  util::Progress progress("static", config_.iterations);
  std::ofstream log(m.run.loss_csv(), std::ios::app);
  if (m.iteration == 0) log << "iteration,loss,l1,ssim,gaussians,seconds\n";
  double test_psnr = NAN;
  TrainResult result;
  while (m.iteration < config_.iterations) {
    if (stop.load()) {
      m.checkpoint(m.elapsed(start));
      result.iteration = m.iteration;
      result.num_gaussians = m.gaussians->size();
      result.seconds = m.elapsed(start);
      result.rollbacks = m.rollbacks;
      m.write_result(result);
      std::cerr << "static: interrupted at iteration " << m.iteration << "; checkpoint written, continue with "
                   "style4d train --resume " << m.run.root.string() << "\n";
      return result;
    }
    ++m.iteration;
    const optim::LossValue value = m.step();
    if (!std::isfinite(value.loss)) {
      m.rollback("the loss became non-finite at iteration " + std::to_string(m.iteration));
      continue;
    }
    if (m.iteration % 10 == 0)
      log << m.iteration << ',' << value.loss << ',' << value.l1 << ',' << value.ssim << ',' << m.gaussians->size() << ','
          << m.elapsed(start) << '\n';
    if (m.iteration % config_.test_every == 0 && m.iteration < config_.iterations)
      test_psnr = m.evaluator.evaluate(m.rast, m.gaussians->params(m.active_degree()), spread(m.test_views, kPeriodicTestViews),
                                       m.frames, m.dataset.background).psnr;
    m.densify_if_due();  // after the test, as graphdeco reports before it densifies or resets opacities
    if (m.iteration % config_.checkpoint_every == 0 && m.iteration < config_.iterations) m.checkpoint(m.elapsed(start));
    std::vector<std::pair<std::string, double>> shown = {{"loss", value.loss}, {"gaussians", m.gaussians->size()}};
    if (!std::isnan(test_psnr)) shown.emplace_back("test_psnr", test_psnr);  // after the first test
    progress.update(m.iteration, shown);
  }
  result.test = m.evaluator.evaluate(m.rast, m.gaussians->params(m.active_degree()), m.test_views, m.frames,
                                     m.dataset.background, m.run.eval_dir());
  if (!m.checkpoint(m.elapsed(start))) throw std::runtime_error("the final state is not finite");
  result.complete = true;
  result.iteration = m.iteration;
  result.num_gaussians = m.gaussians->size();
  result.seconds = m.elapsed(start);
  result.rollbacks = m.rollbacks;
  m.write_result(result);
  progress.finish({{"test_psnr", result.test.psnr}, {"test_ssim", result.test.ssim}, {"gaussians", result.num_gaussians}});
  return result;
}

}  // namespace s4d::train
