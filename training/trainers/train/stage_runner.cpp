#include "s4d/train/stage_runner.h"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <iterator>
#include <stdexcept>

#include "s4d/util/atomic_file.h"
#include "s4d/util/progress.h"

namespace s4d::train {

StageRunner::StageRunner(std::filesystem::path log_path, std::string header)
    : log_path_(std::move(log_path)), header_(std::move(header)) {}

void StageRunner::keep_log_rows(const RunnerStage& stage) {
  std::string text;
  if (std::ifstream in{log_path_, std::ios::binary}) text.assign(std::istreambuf_iterator<char>(in), {});
  const auto commas = std::count(header_.begin(), header_.end(), ',');
  std::string kept = header_ + "\n";
  size_t at = text.find('\n');  // past the header
  while (at != std::string::npos && at + 1 < text.size()) {
    const size_t end = text.find('\n', at + 1);
    if (end == std::string::npos) break;  // a row cut short by a kill
    const std::string row = text.substr(at + 1, end - at - 1);
    if (std::count(row.begin(), row.end(), ',') == commas && stage.keeps_loss_row(row)) kept += row + "\n";
    at = end;
  }
  if (log_.is_open()) log_.close();
  util::write_file_atomic(log_path_, kept);
  log_.open(log_path_, std::ios::app);
  util::require_written(log_, log_path_);
}

bool StageRunner::run(RunnerStage& stage, const std::atomic<bool>& stop) {
  keep_log_rows(stage);
  const StagePlan first = stage.plan();
  util::Progress progress(first.progress_label, first.iterations);
  progress.restart_rate(stage.iteration());
  double test_psnr = NAN;
  for (StagePlan plan = first; stage.iteration() < plan.iterations; plan = stage.plan()) {
    if (plan.iterations != progress.total()) progress.set_total(plan.iterations);  // re-planned (time_budget.h)
    if (stop.load()) {
      stage.before_stop();
      checkpoint(stage);
      std::cerr << plan.name << ": interrupted at iteration " << stage.iteration() << "; checkpoint written, "
                << plan.resume_hint << "\n";
      return false;
    }
    const double loss = stage.step();
    if (!std::isfinite(loss)) {
      recover(stage, "the loss became non-finite at iteration " + std::to_string(stage.iteration()), stage.divergence());
      progress.restart_rate(stage.iteration());
      continue;
    }
    const uint32_t it = stage.iteration();
    if (it % kLossRowEvery == 0) {
      stage.write_loss_row(log_, stage.seconds());
      log_ << std::endl;  // on disk before any later checkpoint
      util::require_written(log_, log_path_);
    }
    if (it % plan.test_every == 0 && it < plan.iterations) test_psnr = stage.periodic_test();
    stage.after_step();
    if (stage.iteration() < it) {  // the stage went back (a probe's second branch): its rows past it go
      keep_log_rows(stage);
      progress.restart_rate(stage.iteration());
      continue;
    }
    if (it % plan.checkpoint_every == 0 && it < plan.iterations && !checkpoint(stage))
      progress.restart_rate(stage.iteration());
    ProgressValues shown = {{"loss", loss}};
    stage.add_progress(shown);
    if (!std::isnan(test_psnr)) shown.emplace_back(plan.test_name, test_psnr);  // after the first test
    progress.update(stage.iteration(), shown);
  }
  progress.set_total(stage.plan().iterations);
  progress.finish(stage.final_test());
  return true;
}

bool StageRunner::checkpoint(RunnerStage& stage) {
  try {
    stage.save(stage.seconds());
  } catch (const StateOutOfRange& e) {  // never written
    recover(stage, "the checkpoint at iteration " + std::to_string(stage.iteration()) + " was refused", e.divergence);
    return false;
  } catch (const std::invalid_argument& e) {  // non-finite parameters: never written
    recover(stage, e.what(), stage.divergence());
    return false;
  }
  return true;
}

void StageRunner::recover(RunnerStage& stage, const std::string& why, const Divergence& now) {
  const StagePlan plan = stage.plan();
  const std::string cause = now.found() ? why + ": " + now.where : why;
  if (now.local && repair(stage, cause, now)) return;
  Recovery rec = stage.recovery();
  stage.restore_last_good();
  stage.recovery() = rec;
  keep_log_rows(stage);
  // A cause the last good state holds too comes back after every rollback: removed, or named.
  const Divergence before = stage.divergence();
  if (before.local && repair(stage, cause + "; the last good state holds it too", before)) return;
  if (before.found())
    throw std::runtime_error(plan.name + ": " + cause + "; the last good state (" + plan.checkpoint.string() +
                             ", iteration " + std::to_string(stage.iteration()) + ") holds the cause too: " +
                             before.where + "; training stopped");
  if (++rec.rollbacks > kMaxRollbacks)
    throw std::runtime_error(plan.name + ": training diverged " + std::to_string(rec.rollbacks) + " times (" + cause +
                             "); the last good state is in " + plan.checkpoint.string());
  rec.lr_scale *= 0.5;
  stage.recovery() = rec;
  std::cerr << plan.name << ": " << cause << "; rolled back to iteration " << stage.iteration()
            << " and halved the learning rates (scale " << rec.lr_scale << ")\n";
}

bool StageRunner::repair(RunnerStage& stage, const std::string& cause, const Divergence& d) {
  Recovery rec = stage.recovery();
  if (rec.repairs >= kMaxRepairs) return false;
  const std::string verb = stage.repair_gaussians(d.gaussians);
  if (verb.empty()) return false;  // a stage that cannot repair
  ++rec.repairs, rec.removed += static_cast<uint32_t>(d.gaussians.size());
  stage.recovery() = rec;
  std::cerr << stage.plan().name << ": " << cause << "; " << verb << " "
            << (d.gaussians.size() == 1 ? "that Gaussian" : "those " + std::to_string(d.gaussians.size()) + " Gaussians")
            << " and went on\n";
  checkpoint(stage);  // the repaired state becomes the last good one
  return true;
}

}  // namespace s4d::train
