#include "s4d/style_gaussians/style_budget.h"

#include <algorithm>
#include <cmath>

#include "s4d/train/time_budget.h"

namespace s4d::style_gaussians {

bool mlp_phase(const StyleConfig& c, uint32_t done) {
  return c.method == run::StyleMethod::full && done + 1 + c.mlp_iterations > c.iterations;
}

StyleLengths fitted_style_lengths(const StyleConfig& start, const StyleConfig& current, uint32_t done, double deadline,
                                  double now, double seconds_per_step, double mlp_ratio) {
  const bool full = start.method == run::StyleMethod::full;
  if (!full) {  // one phase: colours and opacities only
    const uint32_t n = std::max<uint32_t>(1, train::fitted_length(deadline, now, done, seconds_per_step, start.iterations));
    return {n, std::min(start.mlp_iterations, n)};
  }
  if (mlp_phase(current, done)) {  // the MLPs train: the colour-only steps before them stay as they were
    const uint32_t first = current.iterations - current.mlp_iterations;
    const uint32_t mlp = std::max<uint32_t>(
        1, train::fitted_length(deadline, now, done - first, seconds_per_step, start.mlp_iterations));
    return {first + mlp, mlp};
  }
  const uint32_t plain_start = start.iterations - start.mlp_iterations;
  const double f = train::fitted_scale(deadline, now, done, seconds_per_step, mlp_ratio, plain_start, start.mlp_iterations);
  const uint32_t plain = std::max(done, static_cast<uint32_t>(std::lround(f * plain_start)));
  const uint32_t mlp = std::max<uint32_t>(1, static_cast<uint32_t>(std::lround(f * start.mlp_iterations)));
  return {plain + mlp, mlp};
}

}  // namespace s4d::style_gaussians
