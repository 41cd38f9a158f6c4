// Trainer::Impl's tests, the change from the static to the fine stage, and train.json.
#include <algorithm>
#include <fstream>

#include "s4d/run/stage_times.h"
#include "s4d/util/atomic_file.h"
#include "trainer_impl.h"

namespace s4d::train {

namespace {

}  // namespace

nlohmann::json moving_json(const Evaluation& e);

namespace {

nlohmann::json scores_json(const Evaluation& e) {
  nlohmann::json views = nlohmann::json::array();
  for (const ViewScore& s : e.views) views.push_back({{"name", s.name}, {"time", s.time}, {"psnr", s.psnr}, {"ssim", s.ssim}});
  return views;
}

// The "stage_ms" of an earlier train.json; null when there is none or it does not parse.
nlohmann::json previous_stage_ms(const fs::path& train_json) {
  std::ifstream in(train_json);
  const nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
  return j.is_object() && j.contains("stage_ms") ? j["stage_ms"] : nlohmann::json();
}

}  // namespace

bool run_finished(const fs::path& run_dir) {
  std::ifstream in(run::RunDir{run_dir}.train_json());
  const nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
  return j.is_object() && j.value("complete", false) == true;
}

Trainer::Impl::ChoiceViews Trainer::Impl::stage_held_out_views() const {
  std::vector<const data::View*> views;
  for (const data::View* v : test_views)
    if (fine() || v->time <= static_window() + 1e-9) views.push_back(v);
  if (views.empty()) views = test_views;
  views = spread_views(views, kPeriodicTestViews);
  const bool held_out = std::find(train_views.begin(), train_views.end(), views.front()) == train_views.end();
  return {std::move(views), held_out};
}

Evaluation Trainer::Impl::evaluate(const std::vector<const data::View*>& views, const fs::path& save_dir) {
  if (!fine())
    return TrainerCore::evaluate([&](const data::View&) { return gaussians->params(active_degree()); }, views, save_dir);
  return TrainerCore::evaluate([&](const data::View& v) { return deform_to(v.time); }, views, save_dir);
}

void Trainer::Impl::begin_fine_stage(const Evaluation& static_test) {
  static_scores = {{"test_psnr", static_test.psnr}, {"test_ssim", static_test.ssim}, {"moving", moving_json(static_test)},
                   {"test_views", scores_json(static_test)}};
  stage = run::Stage::fine;
  iteration = 0;
  sampler = stage_sampler();
  engine::Recorder rec(ctx, "fresh optimizer");
  for (splat::Attr a : splat::kCloudAttrs) {
    rec.fill(gaussians->moment1(a), 0);
    rec.fill(gaussians->moment2(a), 0);
  }
  for (uint32_t s = 0; s < model::kStatCount; ++s) rec.fill(gaussians->stat(model::Stat(s)), 0);
  ctx.run(std::move(rec));
}

nlohmann::json moving_json(const Evaluation& e) {
  if (!e.moving.psnr) return {{"psnr", nullptr}, {"why", e.moving.why}};
  return {{"psnr", *e.moving.psnr}, {"moving_share", e.moving.moving_share}};
}

std::string Trainer::Impl::degenerate_cause(const TrainResult& r) const {
  std::string cause;
  if (r.num_gaussians < kDegenerateGaussians)
    cause = std::to_string(r.num_gaussians) + " Gaussians left";
  else if (!r.test.views.empty() && r.test.psnr < r.test.background_psnr + kDegenerateMarginDb)
    cause = "the test renders (" + std::to_string(r.test.psnr) + " dB) are no better than the background alone (" +
            std::to_string(r.test.background_psnr) + " dB)";
  if (cause.empty()) return cause;
  // The step that lost most of the model.
  const nlohmann::json* worst = nullptr;
  double worst_share = 0;
  for (const nlohmann::json& e : densify_log) {
    const double before = e.value("before", 0.0), after = e.value("after", 0.0);
    if (before > 0 && (before - after) / before > worst_share) worst_share = (before - after) / before, worst = &e;
  }
  if (worst && worst_share > 0.5)
    cause += "; the model fell from " + std::to_string((*worst)["before"].get<uint64_t>()) + " to " +
             std::to_string((*worst)["after"].get<uint64_t>()) + " Gaussians at the densification of " +
             (*worst)["stage"].get<std::string>() + " iteration " + std::to_string((*worst)["iteration"].get<uint64_t>());
  return cause;
}

void Trainer::Impl::write_result(const TrainResult& r) const {
  nlohmann::json j = {{"stage", run::stage_name(r.stage)},
                      {"complete", r.complete},
                      {"iteration", r.iteration},
                      {"test_psnr", r.test.psnr},
                      {"test_ssim", r.test.ssim},
                      {"moving", moving_json(r.test)},
                      {"background_psnr", r.test.background_psnr},
                      {"seconds", r.seconds},
                      {"num_gaussians", r.num_gaussians},
                      {"rollbacks", r.rollbacks},
                      {"guard_removed", recovery.removed},
                      {"time_budget", time_budget_json(r.seconds)},
                      {"test_views", scores_json(r.test)},
                      {"static", static_scores},
                      {"deform_evaluations", deform_evaluations},
                      {"deform_evaluations_unmasked", deform_evaluations_unmasked},
                      {"moving_gaussians", gaussians->size() - still_count},
                      {"densify_log", densify_log},
                      {"prune_floor", prune_floor_why},
                      {"device", ctx.info().name},
                      {"device_peak_mib", static_cast<double>(ctx.memory_peak()) / (1 << 20)},  // this process's
                      {"data", fs::absolute(dataset.root).string()},
                      {"dataset", facts},
                      {"settings", run::to_json(config)}};
  if (!r.degenerate.empty()) j["degenerate"] = r.degenerate;
  // This process's step times; a process that trained no step (resuming a finished run) keeps the last.
  if (stage_timer && timed_steps > 0) {
    j["stage_ms"] = run::stage_ms_json(stage_timer->totals(), timed_steps);
    const double steps = static_cast<double>(timed_steps);
    j["stage_ms"]["submissions_per_step"] = static_cast<double>(step_submissions) / steps;
    j["stage_ms"]["host_waits_per_step"] = static_cast<double>(step_host_waits) / steps;
  }
  else if (const nlohmann::json last = previous_stage_ms(run.train_json()); !last.is_null()) j["stage_ms"] = last;
  util::write_file_atomic(run.train_json(), j.dump(2) + "\n");
}
}  // namespace s4d::train
