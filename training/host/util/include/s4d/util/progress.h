// Progress reporting for long work, shared by every stage: one line per update on stderr with the
// stage, step/total, rate, ETA and any named values (loss, PSNR...). Rate-limited so tight loops
// can call it every step; on a terminal the line is redrawn in place, elsewhere (CI logs) it is
// printed at most every `min_interval_s` seconds.
#pragma once
#include <chrono>
#include <cstdint>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

namespace s4d::util {

class Progress {
 public:
  Progress(std::string stage, uint64_t total, std::ostream& out, double min_interval_s = 1.0);
  Progress(std::string stage, uint64_t total);  // to std::cerr

  // Reports that `step` of `total` steps are done, with optional named values.
  void update(uint64_t step, const std::vector<std::pair<std::string, double>>& values = {});
  // Prints the final line (always) with the total time.
  void finish(const std::vector<std::pair<std::string, double>>& values = {});

  // Measures the rate (and so the ETA) from `step` now on: a resumed or rolled-back loop's steps
  // before it were not done by this process.
  void restart_rate(uint64_t step);
  // The work was re-planned (a time budget): `total` steps from now on.
  void set_total(uint64_t total) { total_ = total; }
  uint64_t total() const { return total_; }

  double elapsed_s() const;
  // The line update() would print now (exposed for tests).
  std::string format(uint64_t step, const std::vector<std::pair<std::string, double>>& values) const;

 private:
  std::string stage_;
  uint64_t total_;
  std::ostream& out_;
  double min_interval_s_;
  bool interactive_;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_print_;
  uint64_t rate_step_ = 0;
  std::chrono::steady_clock::time_point rate_start_;
  bool printed_ = false;
};

// "1h02m", "3m05s", "12.3s".
std::string format_duration(double seconds);

}  // namespace s4d::util
