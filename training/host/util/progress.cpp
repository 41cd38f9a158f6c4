#include "s4d/util/progress.h"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <iostream>
#include <sstream>

namespace s4d::util {

std::string format_duration(double seconds) {
  if (!std::isfinite(seconds) || seconds < 0) return "?";
  char buf[32];
  if (seconds < 60) {
    std::snprintf(buf, sizeof buf, "%.1fs", seconds);
  } else if (seconds < 3600) {
    const int s = static_cast<int>(seconds);
    std::snprintf(buf, sizeof buf, "%dm%02ds", s / 60, s % 60);
  } else {
    const int m = static_cast<int>(seconds / 60);
    std::snprintf(buf, sizeof buf, "%dh%02dm", m / 60, m % 60);
  }
  return buf;
}

Progress::Progress(std::string stage, uint64_t total, std::ostream& out, double min_interval_s)
    : stage_(std::move(stage)),
      total_(total),
      out_(out),
      min_interval_s_(min_interval_s),
      interactive_(&out == &std::cerr && isatty(STDERR_FILENO)),
      start_(std::chrono::steady_clock::now()),
      last_print_(start_),
      rate_start_(start_) {}

Progress::Progress(std::string stage, uint64_t total) : Progress(std::move(stage), total, std::cerr) {}

void Progress::restart_rate(uint64_t step) {
  rate_step_ = step;
  rate_start_ = std::chrono::steady_clock::now();
}

double Progress::elapsed_s() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

std::string Progress::format(uint64_t step, const std::vector<std::pair<std::string, double>>& values) const {
  std::ostringstream line;
  const double t = elapsed_s();
  line << "[" << stage_ << "] " << step << "/" << total_;
  if (total_ > 0) line << " (" << static_cast<int>(100.0 * static_cast<double>(step) / static_cast<double>(total_)) << "%)";
  const double rate_t = std::chrono::duration<double>(std::chrono::steady_clock::now() - rate_start_).count();
  if (step > rate_step_ && rate_t > 0) {
    const double rate = static_cast<double>(step - rate_step_) / rate_t;
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3g", rate);
    line << " " << buf << " it/s";
    if (total_ >= step) line << " ETA " << format_duration(static_cast<double>(total_ - step) / rate);
  }
  for (const auto& [name, v] : values) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.5g", v);
    line << " " << name << "=" << buf;
  }
  line << " elapsed " << format_duration(t);
  return line.str();
}

void Progress::update(uint64_t step, const std::vector<std::pair<std::string, double>>& values) {
  const auto now = std::chrono::steady_clock::now();
  if (printed_ && std::chrono::duration<double>(now - last_print_).count() < min_interval_s_) return;
  last_print_ = now;
  printed_ = true;
  if (interactive_)
    out_ << "\r\033[K" << format(step, values) << std::flush;
  else
    out_ << format(step, values) << "\n" << std::flush;
}

void Progress::finish(const std::vector<std::pair<std::string, double>>& values) {
  if (interactive_) out_ << "\r\033[K";
  out_ << format(total_, values) << " done\n" << std::flush;
}

}  // namespace s4d::util
