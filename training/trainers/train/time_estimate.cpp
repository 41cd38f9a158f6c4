#include "s4d/train/time_estimate.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace s4d::train {

namespace {

constexpr double kStaticExponent = 0.5;   // static step seconds ~ Gaussians^0.5 (stage scaling)
constexpr double kFineExponent = 0.65;    // 4DGS step seconds ~ Gaussians^0.65
constexpr double kFinePerView = 2.5;      // a 4DGS step per view, in static steps, at equal Gaussians

// Mean of (n(i) / n0)^e over steps [from, until) of a count growing linearly from n0 to n1.
double mean_growth(double n0, double n1, double e) {
  if (n1 <= n0) return 1.0;
  constexpr int kSamples = 64;
  double sum = 0;
  for (int k = 0; k < kSamples; ++k) sum += std::pow((n0 + (n1 - n0) * (k + 0.5) / kSamples) / n0, e);
  return sum / kSamples;
}

std::string duration(double seconds) {
  char buf[48];
  if (seconds < 90) std::snprintf(buf, sizeof buf, "%.0f s", seconds);
  else if (seconds < 90 * 60) std::snprintf(buf, sizeof buf, "%.0f min", seconds / 60);
  else if (seconds < 48 * 3600) std::snprintf(buf, sizeof buf, "%.1f h", seconds / 3600);
  else std::snprintf(buf, sizeof buf, "%.1f days", seconds / 86400);
  return buf;
}

}  // namespace

TimeEstimate estimate_time(const run::TrainConfig& c, double seconds_per_step, uint32_t gaussians) {
  TimeEstimate e;
  e.probe_seconds_per_step = seconds_per_step;
  e.probe_gaussians = gaussians;
  const double n0 = std::max<double>(1, gaussians), n1 = std::max(n0, static_cast<double>(c.budget));
  const double from = std::min<double>(c.densify_from, c.iterations), until = std::min<double>(c.densify_until, c.iterations);
  const double before = from, during = std::max(0.0, until - from), after = std::max(0.0, c.iterations - until);
  e.static_seconds = seconds_per_step * (before + during * mean_growth(n0, n1, kStaticExponent) +
                                         after * std::pow(n1 / n0, kStaticExponent));
  e.fine_seconds = seconds_per_step * kFinePerView * std::max<uint32_t>(1, c.fine_batch) * c.fine_iterations *
                   std::pow(n1 / n0, kFineExponent);
  e.static_seconds_low = seconds_per_step * c.iterations;
  e.fine_seconds_low = seconds_per_step * std::max<uint32_t>(1, c.fine_batch) * c.fine_iterations;
  return e;
}

std::string describe(const TimeEstimate& e, uint32_t probe_steps) {
  char probe[96];
  std::snprintf(probe, sizeof probe, "from %u steps at %.3f s with %u Gaussians", probe_steps, e.probe_seconds_per_step,
                e.probe_gaussians);
  std::string line = "estimate: static stage " + duration(e.static_seconds_low) + " to " + duration(e.static_seconds);
  if (e.fine_seconds > 0) line += ", 4DGS stage " + duration(e.fine_seconds_low) + " to " + duration(e.fine_seconds);
  return line + " (" + probe + "; the high end if the Gaussians fill the budget)";
}

}  // namespace s4d::train
