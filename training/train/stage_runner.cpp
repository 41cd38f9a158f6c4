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
    if (stop.load()) {
      checkpoint(stage);
      std::cerr << plan.name << ": interrupted at iteration " << stage.iteration() << "; checkpoint written, "
                << plan.resume_hint << "\n";
      return false;
    }
    const double loss = stage.step();
    if (!std::isfinite(loss)) {
      roll_back(stage, "the loss became non-finite at iteration " + std::to_string(stage.iteration()));
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
    if (it % plan.checkpoint_every == 0 && it < plan.iterations && !checkpoint(stage))
      progress.restart_rate(stage.iteration());
    ProgressValues shown = {{"loss", loss}};
    stage.add_progress(shown);
    if (!std::isnan(test_psnr)) shown.emplace_back(plan.test_name, test_psnr);  // after the first test
    progress.update(stage.iteration(), shown);
  }
  progress.finish(stage.final_test());
  return true;
}

bool StageRunner::checkpoint(RunnerStage& stage) {
  try {
    stage.save(stage.seconds());
  } catch (const std::invalid_argument& e) {  // non-finite parameters: never written
    roll_back(stage, e.what());
    return false;
  }
  return true;
}

void StageRunner::roll_back(RunnerStage& stage, const std::string& why) {
  const StagePlan plan = stage.plan();
  Recovery now = stage.recovery();
  if (++now.rollbacks > kMaxRollbacks)
    throw std::runtime_error(plan.name + ": training diverged " + std::to_string(now.rollbacks) + " times (" + why +
                             "); the last good state is in " + plan.checkpoint.string());
  now.lr_scale *= 0.5;
  stage.restore_last_good();
  stage.recovery() = now;
  keep_log_rows(stage);
  std::cerr << plan.name << ": " << why << "; rolled back to iteration " << stage.iteration()
            << " and halved the learning rates (scale " << now.lr_scale << ")\n";
}

}  // namespace s4d::train
