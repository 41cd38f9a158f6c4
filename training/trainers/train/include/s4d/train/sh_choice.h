// The SH degree a scene needs, measured rather than preset (TrainConfig::sh_degree_auto): once the
// top degree has trained for a while, the held-out views are rendered with each degree's
// coefficients in turn, and the run keeps the lowest degree whose PSNR is within kShKeepDb of the
// top degree's. A matte scene's higher coefficients only fit its training views' noise, so they
// buy nothing on views the run did not train on, and the run drops them (a quarter of the SH
// floats at degree 1, a sixteenth at degree 3). Written to train.json dataset.recipe.sh_degree.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include <nlohmann/json.hpp>

#include "s4d/run/train_config.h"

namespace s4d::train {

// Held-out PSNR a degree must add to be kept: well above what rounding moves (1e-3 dB), well below
// the 0.2-0.3 dB two seeds of one run differ by, so that a kept degree pays for itself.
constexpr double kShKeepDb = 0.05;

struct ShChoice {
  int degree = 0;
  std::vector<double> psnr;  // held-out PSNR (dB) rendered with degrees 0..top
  uint32_t views = 0;        // how many views it was measured on
  bool held_out = true;      // false: the dataset holds no test view out, so training views were used
  uint32_t at_step = 0;      // steps of the run (both stages) when measured
  nlohmann::json json() const;
};

// The lowest degree whose PSNR is within kShKeepDb of the top degree's (the last entry). Throws
// std::invalid_argument for no entries or a non-finite one.
int lowest_sufficient_degree(std::span<const double> psnr_by_degree);

// The run's step (counted over both stages) after which the choice is made: once the top degree has
// been active for sh_up_every steps; the last step of the run when that comes later.
uint32_t sh_choice_step(const run::TrainConfig& config);

// A new run's settings: a deformation field with the sh head deforms all 16 degree-3 coefficients,
// so nothing can be cut; the choice is turned off, said in one line, and train.json's recipe
// "sh_degree" says why. Null when the choice stays on (or was never on).
nlohmann::json keep_sh_for_field(run::TrainConfig& config);

}  // namespace s4d::train
