// One loop for every training stage (static, 4DGS fine, Style Gaussians): stop requests, the guard
// on a non-finite loss or a checkpoint out of range (a few Gaussians holding the cause are removed;
// otherwise back to the last good state, or a stop naming the cause when that state holds it too),
// checkpoint and test cadence, the
// progress line and loss.csv (its rows hold one line per logged iteration of the state trained:
// rows past a rollback's or a resume's state are dropped). A stage says how to step, save, restore and test
// itself through RunnerStage; what its files hold stays its own.
#pragma once
#include <atomic>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <ostream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "s4d/train/divergence.h"

namespace s4d::train {

using ProgressValues = std::vector<std::pair<std::string, double>>;

// What rollbacks and repairs change: a stage keeps it in its checkpoints so that a resumed run goes
// on with the halved learning rates and counts on.
struct Recovery {
  uint32_t rollbacks = 0;
  double lr_scale = 1;     // multiplies every learning rate
  uint32_t repairs = 0;    // times Gaussians holding the cause were removed or reset
  uint32_t removed = 0;    // Gaussians removed or reset by those repairs
};

// Thrown by RunnerStage::save when the state holds values out of range (nothing written).
struct StateOutOfRange : std::invalid_argument {
  explicit StateOutOfRange(Divergence d) : std::invalid_argument(d.where), divergence(std::move(d)) {}
  Divergence divergence;
};

// What a stage is, for the runner's loop and messages.
struct StagePlan {
  std::string name;            // messages: "static", "fine", "stage 4"
  std::string progress_label;  // the progress line's
  uint32_t iterations = 0;     // the stage's length
  uint32_t test_every = 1, checkpoint_every = 1;
  std::string test_name;             // the periodic test's PSNR in the progress line
  std::string resume_hint;           // how an interrupted stage continues
  std::filesystem::path checkpoint;  // named when training gives up
};

class RunnerStage {
 public:
  virtual ~RunnerStage() = default;
  // Asked at every step: a rollback may change it (the trainer's, back into the static stage).
  virtual StagePlan plan() const = 0;
  virtual uint32_t iteration() const = 0;  // steps done in the stage
  virtual double seconds() const = 0;      // training time over all sessions, now
  virtual Recovery& recovery() = 0;

  // Advances iteration() by one and trains that step; returns its loss (non-finite: rolled back).
  virtual double step() = 0;
  // The last step's loss.csv row, without the line end.
  virtual void write_loss_row(std::ostream& log, double seconds) const = 0;
  // Whether a complete loss.csv row (without its line end) was logged at or before the state the
  // stage has now; the others describe training that a rollback or a kill discarded.
  virtual bool keeps_loss_row(const std::string& row) const = 0;
  // A test on a few views: its PSNR.
  virtual double periodic_test() = 0;
  // What follows a finite step's test (densification, for one). It may take the stage back to an
  // earlier iteration (a probe's second branch): the runner then drops the loss rows past it.
  virtual void after_step() {}
  // The run is interrupted: leave the state a checkpoint can hold (an experiment under way ends).
  virtual void before_stop() {}
  // Values the progress line shows after the loss.
  virtual void add_progress(ProgressValues&) {}
  // Writes a checkpoint and makes it the last good state; StateOutOfRange (or another
  // std::invalid_argument) when the state is not finite or out of range (nothing written).
  virtual void save(double seconds) = 0;
  // Back to the last good state, all of it (Recovery too: the runner sets it after).
  virtual void restore_last_good() = 0;
  // What in the current state is out of range (divergence.h); nothing for a stage that cannot tell.
  virtual Divergence divergence() { return {}; }
  // Repairs a local divergence in the current state: removes these Gaussians (ascending), or resets
  // what the stage trains of them. Returns the verb for the message ("removed", "reset").
  virtual std::string repair_gaussians(const std::vector<uint32_t>&) { return ""; }
  // The stage's closing test over all its test views; returns what the progress line ends with.
  virtual ProgressValues final_test() = 0;
};

class StageRunner {
 public:
  // Rows go to `log_path` under `header` (the column names, without the line end), every
  // kLossRowEvery steps; rows there already are kept as far as the stage keeps them.
  StageRunner(std::filesystem::path log_path, std::string header);

  // Runs `stage` to its length (true) or until `stop` (then checkpoints; false).
  bool run(RunnerStage& stage, const std::atomic<bool>& stop);
  // Saves a checkpoint; false when the state was out of range and the stage was repaired or rolled back instead.
  bool checkpoint(RunnerStage& stage);

  static constexpr uint32_t kLossRowEvery = 10;
  static constexpr uint32_t kMaxRollbacks = 8;  // each halves the learning rates
  static constexpr uint32_t kMaxRepairs = 8;

 private:
  // `why` went wrong and `now` is what the current state holds out of range: removes a few Gaussians
  // holding it, or rolls back (halving the learning rates); throws std::runtime_error naming the cause
  // when the last good state holds it too, or after kMaxRollbacks.
  void recover(RunnerStage& stage, const std::string& why, const Divergence& now);
  // Repairs `d`'s Gaussians and checkpoints the result; false once kMaxRepairs were made.
  bool repair(RunnerStage& stage, const std::string& cause, const Divergence& d);
  // Rewrites loss.csv with its header and the complete rows the stage keeps, then appends.
  void keep_log_rows(const RunnerStage& stage);

  std::filesystem::path log_path_;
  std::string header_;
  std::ofstream log_;
};

}  // namespace s4d::train
