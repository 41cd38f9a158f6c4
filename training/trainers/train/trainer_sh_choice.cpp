// Trainer::Impl's choice of the SH degree from the data (sh_choice.h).
#include <cstdio>
#include <iostream>

#include "s4d/train/sh_choice.h"
#include "s4d/train/split_state.h"
#include "trainer_impl.h"

namespace s4d::train {

void Trainer::Impl::choose_sh_degree_if_due(double seconds) {
  if (!config.sh_degree_auto || config.sh_degree == 0) return;
  const uint32_t done = fine() ? config.iterations + iteration : iteration;
  if (done < sh_choice_step(config)) return;
  const auto [views, held_out] = stage_held_out_views();

  // Each degree's render: the degree the schedule has reached so far is the top (a run cut short may
  // end before it reaches the stored one, whose higher coefficients never trained).
  ShChoice choice{.views = static_cast<uint32_t>(views.size()),
                  .held_out = held_out,
                  .at_step = done};
  const int stored = config.sh_degree, top = active_degree();
  for (int d = 0; d <= top; ++d) {
    config.sh_degree = d;  // active_degree() is at most the setting
    choice.psnr.push_back(evaluate(views).psnr);
  }
  config.sh_degree = stored;
  choice.degree = lowest_sufficient_degree(choice.psnr);

  if (choice.degree < gaussians->sh_degree()) {
    model::Checkpoint cp = snapshot(seconds);
    cp.state = with_sh_degree(cp.state, choice.degree);
    restore(cp);
  }
  config.sh_degree = choice.degree;
  config.sh_degree_auto = false;
  facts["recipe"]["sh_degree"] = choice.json();
  save_run_json();  // a resumed run keeps the choice
  checkpoint(seconds);

  char line[256];
  std::snprintf(line, sizeof line, "SH degree %d of %d: held-out PSNR %.2f dB at degree %d, %.2f dB at degree %d (%u %s views); "
                "a degree is kept when it adds %.2f dB",
                choice.degree, stored, choice.psnr.back(), top, choice.psnr[static_cast<size_t>(choice.degree)], choice.degree,
                choice.views, choice.held_out ? "held-out" : "training", kShKeepDb);
  std::cerr << line << "\n";
}

}  // namespace s4d::train
