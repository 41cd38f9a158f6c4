// The stage runner (stage_runner.h) on a host-only stage: loss.csv rows and checkpoints at their
// cadence, stop requests, rollback to the last good state on a non-finite loss or checkpoint with
// halved learning rates (and loss.csv without the rows it discarded), a resumed stage's loss.csv,
// giving up after kMaxRollbacks, and the guard: a few Gaussians holding the cause removed, a cause
// named in the rollback's line, and a stop when the last good state holds it too.
#include <doctest/doctest.h>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <unistd.h>

#include "s4d/train/stage_runner.h"

using namespace s4d;

namespace {

// Counts steps; a step's loss is NaN for the iterations in `nan_at` (each once) and for
// `nan_always` (every time), a save throws
// std::invalid_argument as a non-finite checkpoint does for those in `bad_save_at` (each once).
struct FakeStage final : train::RunnerStage {
  uint32_t done = 0, length = 25, saved_at = 0, saves = 0, tests = 0, finals = 0;
  std::set<uint32_t> nan_at, bad_save_at;
  train::Recovery rec;
  std::atomic<bool>* stop_after = nullptr;  // set once `stop_at` steps are done
  uint32_t stop_at = 0;
  uint32_t nan_always = 0;  // a step whose loss is always NaN
  // What divergence() finds in the state as it is, and in the last good state once restored.
  train::Divergence cause, good_cause;
  std::vector<uint32_t> removed;

  train::StagePlan plan() const override {
    return {.name = "fake",
            .progress_label = "fake stage",
            .iterations = length,
            .test_every = 7,
            .checkpoint_every = 5,
            .test_name = "test",
            .resume_hint = "run it again",
            .checkpoint = "fake.s4dckpt"};
  }
  uint32_t iteration() const override { return done; }
  double seconds() const override { return 0; }
  train::Recovery& recovery() override { return rec; }
  double step() override {
    ++done;
    if (stop_after && done == stop_at) *stop_after = true;
    return nan_at.erase(done) || done == nan_always ? NAN : 1.0 / done;
  }
  void write_loss_row(std::ostream& log, double) const override { log << done << ",x"; }
  bool keeps_loss_row(const std::string& row) const override { return std::strtoul(row.c_str(), nullptr, 10) <= done; }
  double periodic_test() override { return ++tests; }
  void save(double) override {
    if (bad_save_at.erase(done)) throw std::invalid_argument("a non-finite parameter");
    saved_at = done, ++saves;
  }
  void restore_last_good() override { done = saved_at, rec = {}, cause = good_cause; }
  train::Divergence divergence() override { return cause; }
  std::string repair_gaussians(const std::vector<uint32_t>& rows) override {
    removed.insert(removed.end(), rows.begin(), rows.end());
    cause = good_cause = {};
    return "removed";
  }
  train::ProgressValues final_test() override { return {{"test", ++finals}}; }
};

// A loss.csv of its own per test, removed after it.
struct LossFile {
  std::filesystem::path path =
      std::filesystem::temp_directory_path() / ("s4d_stage_runner_" + std::to_string(getpid()) + ".csv");
  ~LossFile() { std::filesystem::remove(path); }
  std::string text() const {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
  }
};

// Collects what std::cerr receives while it lives.
struct CerrCapture {
  std::ostringstream text;
  std::streambuf* old = std::cerr.rdbuf(text.rdbuf());
  ~CerrCapture() { std::cerr.rdbuf(old); }
};

train::Divergence local_cause() {
  return {.where = "out of range: 'sh' of 2 Gaussians", .gaussians = {3, 4}, .local = true};
}

train::Divergence field_cause() {
  return {.where = "out of range: 'field.planes' at 1 entry (up to 1e+30; in level 0 plane xt)", .gaussians = {}, .local = false};
}

// Runs `stage` to its end on a loss.csv of its own; returns what the runner said on std::cerr.
std::string run_to_end(FakeStage& stage) {
  const LossFile log;
  train::StageRunner runner(log.path, "iteration,what");
  const std::atomic<bool> stop{false};
  CerrCapture err;
  CHECK(runner.run(stage, stop));
  return err.text.str();
}

// Runs `stage` until the runner gives up; returns its error ("" if it did not).
std::string run_error(FakeStage& stage) {
  const LossFile log;
  train::StageRunner runner(log.path, "iteration,what");
  const std::atomic<bool> stop{false};
  try {
    runner.run(stage, stop);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("the stage runner writes rows and checkpoints at their cadence and tests before the end") {
  FakeStage stage;
  const LossFile log;
  train::StageRunner runner(log.path, "iteration,what");
  const std::atomic<bool> stop{false};
  CHECK(runner.run(stage, stop));
  CHECK(log.text() == "iteration,what\n10,x\n20,x\n");
  CHECK(stage.saves == 4);  // 5, 10, 15, 20: the end is the caller's
  CHECK(stage.tests == 3);  // 7, 14, 21
  CHECK(stage.finals == 1);
  CHECK(stage.rec.rollbacks == 0);
}

TEST_CASE("a stop request checkpoints and returns before the next step") {
  FakeStage stage;
  std::atomic<bool> stop{false};
  stage.stop_after = &stop, stage.stop_at = 12;
  const LossFile log;
  train::StageRunner runner(log.path, "iteration,what");
  CHECK_FALSE(runner.run(stage, stop));
  CHECK(stage.done == 12);
  CHECK(stage.saved_at == 12);
  CHECK(stage.finals == 0);
}

TEST_CASE("a non-finite loss or checkpoint rolls back to the last good state and halves the learning rates") {
  FakeStage stage;
  stage.rec.lr_scale = 2;
  stage.nan_at = {13};       // back to 10
  stage.bad_save_at = {20};  // back to 15
  const LossFile log;
  train::StageRunner runner(log.path, "iteration,what");
  const std::atomic<bool> stop{false};
  CHECK(runner.run(stage, stop));
  CHECK(stage.rec.rollbacks == 2);
  CHECK(stage.rec.lr_scale == 0.5);
  CHECK(log.text() == "iteration,what\n10,x\n20,x\n");  // 20's first row went with the rollback to 15
}

TEST_CASE("a stage that keeps diverging stops after kMaxRollbacks rollbacks and names its last checkpoint") {
  FakeStage stage;
  stage.nan_always = 3;
  const std::string what = run_error(stage);
  CHECK(what.find("diverged 9 times") != std::string::npos);
  CHECK(what.find("fake.s4dckpt") != std::string::npos);
  CHECK(stage.rec.rollbacks == train::StageRunner::kMaxRollbacks);
}

TEST_CASE("a resumed stage's loss.csv keeps the complete rows up to its state and drops the rest") {
  const LossFile log;
  std::ofstream(log.path) << "iteration,what\n10,x\n20,x\nbroken\n30,x\n40,";  // 40's row cut short by a kill
  FakeStage stage;
  stage.done = stage.saved_at = 20;  // the checkpoint it resumes from
  train::StageRunner runner(log.path, "iteration,what");
  const std::atomic<bool> stop{false};
  CHECK(runner.run(stage, stop));
  CHECK(log.text() == "iteration,what\n10,x\n20,x\n");  // 30 came after the checkpoint; 25 steps, no row after 20
}

TEST_CASE("guard: a few Gaussians holding the cause are removed and checkpointed, with no rollback") {
  FakeStage stage;
  stage.nan_at = {8};
  stage.cause = local_cause();
  const std::string err = run_to_end(stage);
  CHECK(stage.removed == std::vector<uint32_t>{3, 4});
  CHECK(stage.rec.repairs == 1);
  CHECK(stage.rec.removed == 2);
  CHECK(stage.rec.rollbacks == 0);
  CHECK(stage.rec.lr_scale == 1);
  CHECK(stage.done == 25);  // went on from the step that failed
  CHECK_MESSAGE(err.find("fake: the loss became non-finite at iteration 8: out of range: 'sh' of 2 Gaussians; "
                                    "removed those 2 Gaussians and went on\n") != std::string::npos, err);
}

TEST_CASE("guard: a checkpoint refused for a cause the stage names is repaired the same way") {
  FakeStage stage;
  stage.bad_save_at = {10};
  stage.cause = local_cause();
  const std::string err = run_to_end(stage);
  CHECK(stage.removed == std::vector<uint32_t>{3, 4});
  CHECK(stage.rec.rollbacks == 0);
  CHECK_MESSAGE(err.find("removed those 2 Gaussians and went on") != std::string::npos, err);
}

TEST_CASE("guard: a field tensor out of range is named in the rollback's line when the last good state is clean") {
  FakeStage stage;
  stage.nan_at = {13};
  stage.cause = field_cause();
  const std::string err = run_to_end(stage);
  CHECK(stage.removed.empty());
  CHECK(stage.rec.rollbacks == 1);
  CHECK(stage.rec.lr_scale == 0.5);
  CHECK_MESSAGE(err.find("fake: the loss became non-finite at iteration 13: out of range: 'field.planes' at 1 entry "
                                    "(up to 1e+30; in level 0 plane xt); rolled back to iteration 10") != std::string::npos,
                err);
}

TEST_CASE("guard: a cause the last good state holds too stops training at once, naming it and the checkpoint") {
  FakeStage stage;
  stage.nan_at = {13};
  stage.cause = stage.good_cause = field_cause();
  const std::string what = run_error(stage);
  CHECK_MESSAGE(what.find("the last good state (fake.s4dckpt, iteration 10) holds the cause too: out of range: "
                          "'field.planes' at 1 entry") != std::string::npos, what);
  CHECK_MESSAGE(what.find("training stopped") != std::string::npos, what);
  CHECK(stage.rec.rollbacks == 0);  // no halving that could not help
}

TEST_CASE("guard: repairs stop after kMaxRepairs, and the cause is then named") {
  FakeStage stage;
  stage.nan_always = 3;
  stage.rec.repairs = train::StageRunner::kMaxRepairs;
  stage.cause = stage.good_cause = local_cause();
  const std::string what = run_error(stage);
  CHECK(stage.removed.empty());
  CHECK_MESSAGE(what.find("holds the cause too: out of range: 'sh' of 2 Gaussians") != std::string::npos, what);
}
