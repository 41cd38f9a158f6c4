#include "s4d/optim/lr_schedule.h"

#include <algorithm>
#include <cmath>

namespace s4d::optim {

double LogLinearSchedule::at(uint32_t step) const {
  if (lr0 == 0 || lr1 == 0) return 0;
  const double u = std::clamp(static_cast<double>(step) / std::max<uint32_t>(max_steps, 1), 0.0, 1.0);
  return std::exp((1 - u) * std::log(lr0) + u * std::log(lr1));
}

}  // namespace s4d::optim
