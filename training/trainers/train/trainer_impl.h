// Private to s4d_train: the trainer's state and steps (Trainer::Impl), shared by trainer.cpp and
// the trainer_*.cpp files that define its methods, one job each.
#pragma once

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "s4d/deform/deformation_field.h"
#include "s4d/deform/deformed_cloud.h"
#include "s4d/engine/stage_timer.h"
#include "s4d/densify/densifier.h"
#include "s4d/model/checkpoint.h"
#include "s4d/model/trainable_gaussians.h"
#include "s4d/optim/adam_tensor.h"
#include "s4d/train/budget_growth.h"
#include "s4d/train/divergence.h"
#include "s4d/train/field_box.h"
#include "s4d/train/stage_runner.h"
#include "s4d/train/time_budget.h"
#include "s4d/train/trainer.h"
#include "s4d/train/trainer_core.h"

namespace s4d::train {

namespace fs = std::filesystem;

namespace detail {

// Adam groups: one per Gaussian attribute with the SH rows split into DC and the rest, then the
// deformation field's planes and MLP.
enum Group : uint32_t { gMeans, gScales, gQuats, gOpacity, gShDc, gShRest, gPlanes, gMlp, gCount };

}  // namespace detail

// The shared state and steps (views, frames, rasterizer, loss, Adam, evaluator, guard) are the
// TrainerCore's; the Gaussians, the field and the stages are the Impl's own.
struct Trainer::Impl : TrainerCore {
  run::RunDir run;
  // The run's settings; under a time budget its plans change the stages' lengths and schedules.
  run::TrainConfig& config;
  const data::Dataset& dataset;
  std::vector<const data::View*> static_views;  // the static stage's: train views with time <= static_max_time
  std::unique_ptr<model::TrainableGaussians> gaussians;
  densify::Densifier densifier;

  // Stage 2 state: the field, its Adam moments, the deformed Gaussians and a batch's scratch.
  std::unique_ptr<deform::DeformationField> field;
  std::array<float, 3> aabb_min{}, aabb_max{};
  optim::AdamTensor field_planes, field_mlp;  // "field.planes", "field.mlp"
  deform::DeformedCloud deformed;  // the Gaussians at the time of the view in hand (deform_to)
  model::CloudArrays<engine::Buffer> scratch_grad;
  engine::Buffer batch_stats;
  uint32_t sized_for = UINT32_MAX;  // Gaussian count the stage-2 buffers hold
  // The last still_count Gaussians do not move and skip the field (config.static_motion); 0 until
  // measured and again after densification.
  uint32_t still_count = 0;
  bool field_fitted = false;  // the field's box was fitted to what moves (field_box.h); once per run
  double deform_evaluations = 0, deform_evaluations_unmasked = 0;  // Gaussians the field evaluated / would have
  // Times the stages of this process's steps (train.json "stage_ms"); set while run() runs.
  engine::StageTimer* stage_timer = nullptr;
  uint64_t timed_steps = 0;
  uint64_t step_submissions = 0, step_host_waits = 0;  // over the timed steps (engine::Context counters)

  run::Stage stage = run::Stage::coarse;
  uint32_t iteration = 0;  // within the stage
  nlohmann::json static_scores;  // the static stage's final test, once done
  nlohmann::json facts;          // the data's layout, background, initialisation and recipe (dataset_facts)
  // Every densification's counts, and every seeding's (train.json "densify_log"; kept in checkpoints).
  nlohmann::json densify_log = nlohmann::json::array();
  // The fewest Gaussians pruning may leave (visible_content.h); 0 until measured at the first densification.
  uint32_t prune_floor = 0;
  nlohmann::json prune_floor_why;
  // Resumed from the previous checkpoint because the newest was damaged: the next checkpoint replaces
  // the newest without rotating it over the good previous one.
  bool newest_damaged = false;
  // The time budget's plans (config.time_budget > 0; time_budget.h).
  BudgetState time_plan;
  // The Gaussian budget's growth (budget_growth.h; the recipe's "gaussian_budget") and the paired
  // probe under way: the state before its densification, then the kept branch's end.
  BudgetGrowth growth;
  struct GrowthProbe {
    enum Phase { none, kept, grown } phase = none;
    model::Checkpoint before, kept_end;
    BudgetProbe record;
  } probe;
  bool probe_held = false;  // set while an abandoned probe's densification is done again

  // The runner's view of the current stage (trainer.cpp).
  struct Steps;

  // ---- Small queries and the constructor (trainer.cpp).
  Impl(engine::Context& c, run::RunDir r, run::TrainConfig& cfg, const data::Dataset& d);
  bool fine() const { return stage == run::Stage::fine; }
  // Each stage draws from its own views, with its own seeded order.
  ViewSampler stage_sampler() const {
    const size_t views = fine() ? train_views.size() : static_views.size();
    return ViewSampler(static_cast<uint32_t>(std::max<size_t>(views, 1)), config.seed + (fine() ? 1u : 0u));
  }
  uint32_t stage_iterations() const { return fine() ? config.fine_iterations : config.iterations; }
  int active_degree() const {
    return run::active_sh_degree(config, fine() ? config.iterations + iteration : iteration);  // not reset (3.3)
  }
  bool head(uint32_t bit) const { return (config.field_heads & bit) != 0; }
  double static_window() const { return std::min(config.max_time, config.static_max_time); }
  double elapsed(const std::chrono::steady_clock::time_point& start) const {
    return seconds_before + std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  TrainResult result(bool complete, double seconds, Evaluation test) const {
    return {complete, stage, iteration, gaussians->size(), seconds, recovery.rollbacks, std::move(test)};
  }

  // ---- The field, snapshots, checkpoints and loss.csv (trainer_checkpoint.cpp).
  // The field, sized from the initial cloud's bounds (validated here, so a field the device cannot
  // run fails before any training).
  void make_field(uint32_t seed);
  nlohmann::json meta(double seconds) const;
  model::Checkpoint snapshot(double seconds) const;
  void restore(const model::Checkpoint& cp);
  // Saves the current state as the checkpoint and the PLY and makes it the last good state;
  // StateOutOfRange when it holds values out of range (divergence.h; nothing written).
  void checkpoint(double seconds);
  // run.json with the settings and the data's facts as they now are (a plan or a choice changed
  // them), so that a resumed run continues with them.
  void save_run_json() const;
  // What `state` holds out of range, the field's parts named.
  Divergence divergence(const model::Checkpoint& state) const;
  // The current state without these Gaussians (the still mask is measured again).
  void remove_gaussians(const std::vector<uint32_t>& rows, double seconds);

  // ---- Stage 1 and what both stages' steps share (trainer_static_step.cpp).
  void set_learning_rates(uint32_t step);
  // Uploads a view's target image; returns its camera.
  // One submission: the Gaussians that `params` records (nothing to record for stage 1's, the
  // deformation for stage 2's), their forward and the loss against the target; the same again
  // after the rasterizer's instance buffers grew. Returns the loss (maybe non-finite).
  void record_adam(engine::Recorder& rec);
  // Stage 1: one view, the canonical Gaussians as they are. Returns the loss (maybe non-finite).
  optim::LossValue static_step();

  // ---- Stage 2: the deformation field over a batch of views (trainer_fine_step.cpp).
  void size_stage2_buffers();
  deform::CanonicalGaussians canonical() const;
  // Deforms the canonical Gaussians to `time` and returns the rasterizer's view of the result:
  // recorded into `rec`, or in a submission of its own, waited for.
  splat::GaussianParams record_deform(engine::Recorder& rec, double time);
  splat::GaussianParams deform_to(double time);
  // The fine stage's next view. With fine_time_ramp > 0 the time window opens from the first frame
  // to the last over that fraction of the stage, so the field learns motion frame by frame: a large
  // move (a box sliding further than its size between distant times) is found by small steps,
  // which photometric gradients can follow. With `front`, the view comes from the window's newest
  // fine_time_front of time. Views outside are skipped in the sampler's order, so the choice stays
  // deterministic and resumable.
  const data::View& next_fine_view(bool front);
  // The end of the fine stage's open time window (1 once the ramp is over).
  double fine_window() const;
  // Stage 2: a batch of views, each deformed to its time; gradients summed over the batch.
  optim::LossValue fine_step();

  // ---- Changes to the cloud's layout: densification and the motion split (trainer_densify.cpp).
  // Moves the Gaussians `mask` marks still to the end of memory, every per-Gaussian array with
  // them, so that the field runs over the moving prefix only.
  void apply_mask(const std::vector<uint32_t>& mask);
  // Each Gaussian's lowest and highest mean (3 floats each) over motion_samples times in [0, 1].
  void path_bounds(std::vector<float>& lo, std::vector<float>& hi);
  // The time axis for the paths of the Gaussians whose bounds (path_bounds) span move_limit.
  FieldTime fit_time(const std::vector<float>& lo, const std::vector<float>& hi, double move_limit);
  // Marks the Gaussians whose mean moves less than static_motion x extent between any two of
  // motion_samples times as still (ALGORITHMS.md has no such step: it is this project's "deform
  // only what moves").
  void update_mask();
  bool mask_due() const;
  void densify_if_due(double seconds);
  // One densification now, at most `budget` Gaussians after it, then seeding; logged.
  densify::DensifyResult densify_now(const std::string& when, uint32_t budget);
  // The prune rules of one densification, with min_opacity lowered so that at least prune_floor
  // Gaussians survive it; says so in one line when it does.
  densify::DensifyRules prune_rules_with_floor(densify::DensifyRules rules, const std::string& when);
  void log_densify(const std::string& when, const densify::DensifyResult& r, uint32_t below_opacity, float min_opacity);
  // Renders config.seed_views training views and seeds Gaussians where they miss content
  // (trainer_seed.cpp); logs the count in densify_log.
  void seed_missing_content(const std::string& when);
  // The training views seeding looks at: the static stage's; in the fine stage the newest
  // fine_time_front of the open window while it opens (what was just opened is what the model
  // misses), else every open view.
  std::vector<const data::View*> seed_pool() const;

  // ---- The SH degree chosen from the data (trainer_sh_choice.cpp, sh_choice.h).
  // Once due: renders the held-out views at each degree, keeps the lowest that serves them as well,
  // cuts the SH to it, records the evidence in the recipe, rewrites run.json and checkpoints.
  void choose_sh_degree_if_due(double seconds);

  // ---- The field's box fitted to what moves (trainer_field_box.cpp, field_box.h).
  // Once due: measures the Gaussians' paths, fits the box, resamples the planes and their moments
  // onto it, records the evidence in the recipe, rewrites run.json and checkpoints.
  // True when it fitted (this step); its one-off cost is then no step's.
  bool fit_field_box_if_due(double seconds);

  // ---- The Gaussian budget grown while held-out error falls (trainer_budget_growth.cpp, budget_growth.h).
  // The budget densification keeps to now: the probe's grown branch's, the growth's, or the setting.
  uint32_t densify_budget() const;
  // Whether a densification now could start a probe (growth open, none under way, a clear window,
  // enough Gaussians that the budget can hold it back).
  bool budget_probe_possible() const;
  // After a densification that the budget held back, from the state before it: the kept branch starts.
  void start_budget_probe(model::Checkpoint before, const densify::DensifyResult& r);
  // At a probe's branch end (first in the step's after-work): the kept branch's end goes back to the
  // state before the densification and opens the grown branch, whose densification the rest of the
  // after-work then does; the grown branch's end decides, goes on from the better branch and
  // records the probe.
  void budget_probe_step(double seconds);
  // A rollback or a repair changed the state under a probe: it ends without a decision.
  void cancel_budget_probe() { probe = {}; }
  // The run stops during a probe: back to the kept branch's start (the densification done at the
  // budget decided), so that its checkpoint holds what run.json's budget says.
  void abandon_budget_probe(double seconds);

  // ---- The time budget (trainer_time_budget.cpp).
  // Marks where a stage's step times are measured from: after the static stage's first
  // kTimeMarkAt steps (shaders and buffers warm), and at the fine stage's start.
  void mark_time(double seconds) { time_plan.from_iteration = iteration, time_plan.from_seconds = seconds; }
  // Plans the stages' lengths when a plan is due (time_budget.h); rewrites run.json with them.
  void plan_time_if_due(double seconds);
  // train.json's "time_budget": given and taken seconds, the static share, every plan; null without one.
  nlohmann::json time_budget_json(double seconds) const;

  // ---- Tests, the stage change and train.json (trainer_report.cpp).
  Evaluation evaluate(const std::vector<const data::View*>& views, const fs::path& save_dir = {});
  // The held-out views of what the stage models (the static stage's time window, or every time),
  // spread over kPeriodicTestViews; the choices made from the data measure on them. `held_out` is
  // false where the dataset holds no view out and the test views are training ones.
  struct ChoiceViews {
    std::vector<const data::View*> views;
    bool held_out = true;
  };
  ChoiceViews stage_held_out_views() const;
  // The static stage is complete: keep its scores and move on to the fine stage (4DGaussians calls
  // training_setup again: fresh Adam moments, statistics and schedules).
  void begin_fine_stage(const Evaluation& static_test);
  void write_result(const TrainResult& r) const;
  // TrainResult::degenerate's text for a finished run ("" when the model is sound).
  std::string degenerate_cause(const TrainResult& r) const;
};

}  // namespace s4d::train
