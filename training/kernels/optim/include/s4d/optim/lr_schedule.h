// Learning-rate schedules of 3DGS / 4DGaussians (ALGORITHMS.md 2.1): the position learning rate
// decays log-linearly from lr0 to lr1 over max_steps (graphdeco's get_expon_lr_func; its delay
// terms are inert with lr_delay_steps = 0, so they are left out).
#pragma once
#include <cstdint>

namespace s4d::optim {

struct LogLinearSchedule {
  double lr0 = 0, lr1 = 0;  // at step 0 and from max_steps on
  uint32_t max_steps = 1;

  // exp((1 - u) ln lr0 + u ln lr1) with u = clamp(step / max_steps, 0, 1); 0 when lr0 or lr1 is 0
  // (a frozen group), as in graphdeco.
  double at(uint32_t step) const;
};

}  // namespace s4d::optim
