// Trainer::Impl's tests, the change from the static to the fine stage, and train.json.
#include <fstream>

#include "s4d/run/stage_times.h"
#include "s4d/util/atomic_file.h"
#include "trainer_impl.h"

namespace s4d::train {

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

Evaluation Trainer::Impl::evaluate(const std::vector<const data::View*>& views, const fs::path& save_dir) {
  if (!fine())
    return evaluator.evaluate(rast, [&](const data::View&) { return gaussians->params(active_degree()); }, views, frames,
                              dataset.background, save_dir);
  return evaluator.evaluate(rast, [&](const data::View& v) { return deform_to(v.time); }, views, frames,
                            dataset.background, save_dir);
}

void Trainer::Impl::begin_fine_stage(const Evaluation& static_test) {
  static_scores = {{"test_psnr", static_test.psnr}, {"test_ssim", static_test.ssim}, {"test_views", scores_json(static_test)}};
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

void Trainer::Impl::write_result(const TrainResult& r) const {
  nlohmann::json j = {{"stage", run::stage_name(r.stage)},
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
                      {"moving_gaussians", gaussians->size() - still_count},
                      {"device", ctx.info().name},
                      {"device_peak_mib", static_cast<double>(ctx.memory_peak()) / (1 << 20)},  // this session's
                      {"data", fs::absolute(dataset.root).string()},
                      {"dataset", facts},
                      {"settings", run::to_json(config)}};
  // This session's step times; a session that trained no step (resuming a finished run) keeps the last.
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
