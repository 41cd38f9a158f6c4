// Trainer's public methods and the Impl constructor; Impl's other methods are in trainer_*.cpp,
// one job each (trainer_impl.h lists them).
#include "s4d/train/trainer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <optional>
#include <stdexcept>

#include "s4d/io/ply_gaussians.h"
#include "s4d/model/checkpoint.h"
#include "s4d/run/run_json.h"
#include "s4d/train/scene_motion.h"
#include "s4d/train/sh_choice.h"
#include "s4d/run/run_lock.h"
#include "s4d/run/run_size.h"
#include "s4d/run/stage_times.h"
#include "s4d/train/budget_growth.h"
#include "s4d/train/data_recipe.h"
#include "s4d/train/init_cloud.h"
#include "s4d/train/time_estimate.h"
#include "s4d/util/atomic_file.h"
#include "s4d/util/free_space.h"
#include "trainer_impl.h"

namespace s4d::train {

namespace {

constexpr size_t kFrameCacheBytes = size_t{1} << 30;
// Static steps timed for the run's time estimate, after the first ones, which compile pipelines and
// fill the frame cache (on a 2-core lavapipe the first 10 ran 3x slower than the rest).
constexpr uint32_t kProbeFrom = 20, kProbeSteps = 30;

// Cap on the points a run starts from: 4DGaussians downsamples its clouds to 40k, and starting at
// the Gaussian budget would leave densification no room.
uint32_t max_initial_points(const run::TrainConfig& c) { return std::min<uint32_t>(40000, std::max<uint32_t>(1, c.budget / 2)); }

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

std::vector<const data::View*> select_views(const data::Dataset& d, const run::TrainConfig& c, bool test) {
  std::vector<const data::View*> out;
  for (const data::View& v : d.views)
    if (v.test == test && v.time <= c.max_time + 1e-9) out.push_back(&v);
  return out;
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
std::optional<model::LoadedCheckpoint> checkpoint_to_resume(const run::RunDir& run) {
  if (fs::exists(run.checkpoint()) || fs::exists(run.previous_checkpoint()))
    return model::read_checkpoint_or_previous(run.checkpoint(), run.previous_checkpoint());
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
                             "new run with another --run, or delete " + run.root.string() + " to train this one again)");
  std::cerr << run.root.string() << ": no checkpoint yet (the run stopped before its first) and no results to lose; "
            << "training it from the start\n";
  return std::nullopt;
}

// Refuses a run whose next checkpoint cannot be written (run_size.h); warns when the disk would
// fill before the Gaussian budget is reached.
void require_room_for(const fs::path& run_dir, const run::TrainConfig& config, size_t gaussians) {
  const run::RunSize size = run::run_size(config, static_cast<uint32_t>(gaussians));
  const uint64_t free = util::require_room(run_dir, size.least, size.largest_file,
                                           "a checkpoint of " + std::to_string(gaussians) +
                                               " Gaussians (written beside the current one)");
  if (free < size.at_budget)
    std::cerr << "warning: " << run_dir.string() << ": " << util::byte_size(free) << " free; the run's checkpoints at its "
              << "budget of " << config.budget << " Gaussians need about " << util::byte_size(size.at_budget) << "\n";
}

}  // namespace

Trainer::Impl::Impl(engine::Context& c, run::RunDir r, run::TrainConfig& cfg, const data::Dataset& d)
    : TrainerCore(c, {.name = "training",
                      .frames_of = &d,
                      .train_views = select_views(d, cfg, false),
                      .test_views = select_views(d, cfg, true),
                      .frame_cache_bytes = kFrameCacheBytes,
                      .adam_groups = detail::gCount,
                      .seed = cfg.seed,
                      .background = d.background,
                      .recovery = {.lr_scale = cfg.lr_scale}}),
      run(std::move(r)), config(cfg), dataset(d), densifier(c) {
  for (const data::View* v : train_views)
    if (v->time <= cfg.static_max_time + 1e-9) static_views.push_back(v);
  sampler = stage_sampler();
  if (static_views.empty())
    throw std::runtime_error(d.root.string() + ": no training views with time <= " +
                             std::to_string(std::min(cfg.max_time, cfg.static_max_time)) + " for the static stage");
}

Trainer::Trainer(engine::Context& ctx, const fs::path& data_dir, const run::TrainConfig& config, const fs::path& run_dir,
                 std::optional<data::Dataset> loaded)
    : config_(config) {
  run::validate(config_, "training settings");
  // The folder's .lock is the caller's run lock (run_lock.h), taken before the run is created.
  if (fs::exists(run_dir) && !(fs::is_directory(run_dir) && run::empty_but_for_lock(run_dir)))
    throw std::invalid_argument(run_dir.string() + " already exists and is not empty; continue it with style4d train --run " +
                                run_dir.string() + " or choose another --run");
  dataset_ = loaded ? std::move(*loaded) : data::load_dataset(data_dir, load_options(config_, false));
  config_.background = dataset_.background;
  if (!dataset_.background_conflict.empty())
    std::cerr << "warning: " << dataset_.root.string() << ": background: " << dataset_.background_conflict << "\n";
  nlohmann::json recipe = adapt_to_data(config_, dataset_);
  InitReport init;
  const io::GaussianCloud initial = initial_cloud(dataset_, config_.sh_degree, config_.random_init_points,
                                                  max_initial_points(config_), config_.seed, &init);
  impl_ = std::make_unique<Impl>(ctx, run::RunDir{run_dir}, config_, dataset_);
  // Before the field is made; the frames the check decodes stay cached for training.
  if (config_.fine_iterations > 0) recipe["deformation_field"] = skip_field_if_still(config_, dataset_, impl_->frames);
  if (nlohmann::json kept = keep_sh_for_field(config_); !kept.is_null()) recipe["sh_degree"] = kept;
  impl_->growth = plan_budget_growth(config_);
  recipe["gaussian_budget"] = impl_->growth.json();
  impl_->facts = dataset_facts(dataset_, init, recipe);
  std::tie(impl_->aabb_min, impl_->aabb_max) = bounds(initial.means);
  impl_->make_field(config_.seed);  // before anything is written: a field the device cannot run fails here
  require_room_for(run_dir, config_, initial.size());  // and a disk that cannot take the first checkpoint
  fs::create_directories(run_dir / "checkpoint");
  fs::create_directories(run_dir / "geometry");
  // "stage" names what the run's geometry is, for readers of a run (render, viewer).
  run::write_run_json(impl_->run, {.data = data_dir, .stage = run::last_stage(config_), .dataset = impl_->facts,
                                   .settings = config_});
  impl_->gaussians = std::make_unique<model::TrainableGaussians>(ctx, initial, "gaussians");
  impl_->last_good = impl_->snapshot(0);
}

Trainer::Trainer(engine::Context& ctx, const run::RunDir& run, const run::RunJson& run_json) {
  config_ = run_json.settings;
  // What the run's geometry is (render reads it): a hand-edited stage would be trained and then not render.
  const run::Stage expected_stage = run::last_stage(config_);
  if (run_json.stage && *run_json.stage != expected_stage)
    throw std::runtime_error(run.run_json().string() + ": field 'stage' = \"" + run::geometry_name(*run_json.stage) +
                             "\": expected \"" + run::geometry_name(expected_stage) +
                             "\" for settings with fine_iterations = " + std::to_string(config_.fine_iterations));
  std::optional<model::LoadedCheckpoint> from = checkpoint_to_resume(run);  // before anything is loaded or written
  dataset_ = data::load_dataset(run_json.data, load_options(config_, true));
  // Runs from before the recipe stored no resolved value; nothing is left to the data on resume.
  const nlohmann::json recipe = adapt_to_data(config_, dataset_);
  impl_ = std::make_unique<Impl>(ctx, run, config_, dataset_);
  impl_->facts = run_json.dataset.is_null() ? dataset_facts(dataset_, {}, recipe) : run_json.dataset;
  // Runs from before the growth have no record: their budget is the setting's.
  if (const nlohmann::json& f = impl_->facts; f.contains("recipe") && f["recipe"].contains("gaussian_budget"))
    impl_->growth = BudgetGrowth::from_json(f["recipe"]["gaussian_budget"]);
  if (from) {
    try {
      impl_->restore(from->checkpoint);
      // Only here: a restore within a run (a rollback, a choice, a refit) keeps the seconds spent.
      impl_->seconds_before = from->checkpoint.meta.at("seconds").get<double>();
    } catch (const std::exception& e) {
      throw std::runtime_error(from->path.string() + ": " + e.what());
    }
    if (!from->newest_problem.empty()) {
      impl_->newest_damaged = true;
      std::cerr << "warning: " << from->newest_problem << "; resuming from the previous checkpoint " << from->path.string()
                << " (" << run::stage_name(impl_->stage) << " stage, iteration " << impl_->iteration << ")\n";
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
  require_room_for(run.root, config_, impl_->gaussians->size());
}

std::unique_ptr<Trainer> Trainer::resume(engine::Context& ctx, const fs::path& run_dir) {
  const run::RunDir run{run_dir};
  if (!fs::exists(run.run_json()))
    throw std::runtime_error(run.run_json().string() + ": missing; " + run_dir.string() + " is not a training run");
  if (run_finished(run_dir))
    throw std::runtime_error(run.train_json().string() + ": the run is finished (complete); its results are not trained again");
  return std::unique_ptr<Trainer>(new Trainer(ctx, run, run::read_run_json(run)));
}

Trainer::~Trainer() = default;

// The stage the trainer is in, as the runner drives it (both stages share one Impl).
struct Trainer::Impl::Steps final : RunnerStage {
  Steps(Impl& impl, std::chrono::steady_clock::time_point from) : m(impl), start(from) {}

  StagePlan plan() const override {
    const std::string name = run::stage_name(m.stage);
    return {.name = name,
            .progress_label = name,
            .iterations = m.stage_iterations(),
            .test_every = m.config.test_every,
            .checkpoint_every = m.config.checkpoint_every,
            .test_name = "test_psnr",
            .resume_hint = "continue with style4d train --run " + m.run.root.string(),
            .checkpoint = m.run.checkpoint()};
  }
  uint32_t iteration() const override { return m.iteration; }
  double seconds() const override { return m.elapsed(start); }
  Recovery& recovery() override { return m.recovery; }

  double step() override {
    const engine::StageTimer::Window window(m.stage_timer);
    ++m.timed_steps;
    ++m.iteration;
    const uint64_t submissions = m.ctx.submissions(), waits = m.ctx.host_waits();
    value = m.fine() ? m.fine_step() : m.static_step();
    m.step_submissions += m.ctx.submissions() - submissions;
    m.step_host_waits += m.ctx.host_waits() - waits;
    return value.loss;
  }
  void write_loss_row(std::ostream& log, double seconds) const override {
    log << run::stage_name(m.stage) << ',' << m.iteration << ',' << value.loss << ',' << value.l1 << ',' << value.ssim << ','
        << m.gaussians->size() << ',' << seconds;
  }
  // Rows of the static stage, and of the current stage up to its iteration.
  bool keeps_loss_row(const std::string& row) const override {
    const size_t comma = row.find(',');
    const std::optional<run::Stage> row_stage = run::parse_stage(row.substr(0, comma));
    const auto row_iteration = std::strtoul(row.c_str() + comma + 1, nullptr, 10);
    return row_stage == m.stage ? row_iteration <= m.iteration : row_stage == run::Stage::coarse;
  }
  double periodic_test() override { return m.evaluate(spread_views(m.test_views, kPeriodicTestViews)).psnr; }
  void after_step() override {
    const engine::StageTimer::Window window(m.stage_timer);
    const engine::StageScope timed(m.ctx, "densify");
    m.budget_probe_step(seconds());  // may go back to the probe's densification (budget_growth.h)
    m.densify_if_due(seconds());  // after the test, as graphdeco reports before it densifies or resets opacities
    const double before_fit = seconds();
    // The fit's paths and resampling are no step's cost: the time budget's next plan leaves them out.
    if (m.fit_field_box_if_due(before_fit)) m.time_plan.from_seconds += seconds() - before_fit;
    if (m.mask_due()) m.update_mask();
    m.choose_sh_degree_if_due(seconds());
    m.plan_time_if_due(seconds());
  }
  void add_progress(ProgressValues& shown) override {
    shown.emplace_back("gaussians", static_cast<double>(m.gaussians->size()));
    shown.emplace_back("device_mib", static_cast<double>(m.ctx.memory_in_use()) / (1 << 20));  // bench/soak.sh plots it
    // A fresh run tells its expected length once its first steps are timed.
    const bool fresh = m.stage == run::Stage::coarse && m.seconds_before == 0;
    if (fresh && m.iteration == kProbeFrom) probe_start = seconds();
    if (fresh && m.iteration == kProbeFrom + kProbeSteps) {
      const TimeEstimate e =
          estimate_time(m.config, (seconds() - probe_start) / kProbeSteps, static_cast<uint32_t>(m.gaussians->size()));
      std::cerr << describe(e, kProbeSteps) << " on " << m.ctx.info().name << "\n";
      m.facts["estimate"] = {{"static_seconds", e.static_seconds}, {"fine_seconds", e.fine_seconds},
                             {"static_seconds_low", e.static_seconds_low}, {"fine_seconds_low", e.fine_seconds_low},
                             {"probe_seconds_per_step", e.probe_seconds_per_step}, {"probe_gaussians", e.probe_gaussians}};
    }
  }
  void save(double seconds) override { m.checkpoint(seconds); }
  void before_stop() override { m.abandon_budget_probe(seconds()); }
  void restore_last_good() override {
    m.cancel_budget_probe();
    m.restore(m.last_good);
  }
  Divergence divergence() override { return m.divergence(m.snapshot(seconds())); }
  std::string repair_gaussians(const std::vector<uint32_t>& rows) override {
    m.cancel_budget_probe();
    m.remove_gaussians(rows, seconds());
    return "removed";
  }
  ProgressValues final_test() override {
    test = m.evaluate(m.test_views, last() ? m.run.eval_dir() : fs::path{});
    return {{"test_psnr", test.psnr}, {"test_ssim", test.ssim}, {"gaussians", static_cast<double>(m.gaussians->size())}};
  }

  bool last() const { return m.fine() || m.config.fine_iterations == 0; }

  Impl& m;
  std::chrono::steady_clock::time_point start;
  optim::LossValue value{};  // the last step's
  double probe_start = 0;
  Evaluation test;  // the last stage's closing test
};

TrainResult Trainer::run(const std::atomic<bool>& stop) {
  Impl& m = *impl_;
  engine::StageTimer timer(m.ctx, run::kStepStages);
  struct Installed {  // the timer is gone once run() returns
    Impl& m;
    ~Installed() { m.stage_timer = nullptr; }
  } installed{m};
  m.stage_timer = &timer;
  StageRunner runner(m.run.loss_csv(), "stage,iteration,loss,l1,ssim,gaussians,seconds");
  Impl::Steps steps(m, std::chrono::steady_clock::now());
  while (true) {
    if (!runner.run(steps, stop)) {
      TrainResult r = m.result(false, steps.seconds(), {});
      m.write_result(r);
      return r;
    }
    if (steps.last()) {
      // Refused: repaired (the closing test runs again) or rolled back (the stage goes on).
      if (!runner.checkpoint(steps)) continue;
      TrainResult r = m.result(true, steps.seconds(), std::move(steps.test));
      r.degenerate = m.degenerate_cause(r);
      m.write_result(r);
      return r;
    }
    m.begin_fine_stage(steps.test);
    m.mark_time(steps.seconds());
    runner.checkpoint(steps);
  }
}

}  // namespace s4d::train
