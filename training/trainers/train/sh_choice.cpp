#include "s4d/train/sh_choice.h"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <stdexcept>

#include "s4d_deform.h"

namespace s4d::train {

nlohmann::json ShChoice::json() const {
  return {{"degree", degree},
          {"psnr_by_degree", psnr},
          {"keep_db", kShKeepDb},
          {"views", views},
          {"held_out", held_out},
          {"at_step", at_step},
          {"why", "the lowest degree whose held-out PSNR is within keep_db of degree " + std::to_string(psnr.size() - 1) +
                      "'s; the coefficients above it are dropped"}};
}

int lowest_sufficient_degree(std::span<const double> psnr_by_degree) {
  if (psnr_by_degree.empty()) throw std::invalid_argument("lowest_sufficient_degree: no degrees measured");
  for (double p : psnr_by_degree)
    if (!std::isfinite(p)) throw std::invalid_argument("lowest_sufficient_degree: a non-finite PSNR");
  const double top = psnr_by_degree.back();
  size_t d = 0;
  while (psnr_by_degree[d] < top - kShKeepDb) ++d;  // ends at the top degree at the latest
  return static_cast<int>(d);
}

uint32_t sh_choice_step(const run::TrainConfig& config) {
  const uint64_t after = uint64_t(config.sh_degree + 1) * std::max<uint32_t>(1, config.sh_up_every);
  const uint64_t last = uint64_t(config.iterations) + config.fine_iterations;
  return static_cast<uint32_t>(std::min(after, last));
}

nlohmann::json keep_sh_for_field(run::TrainConfig& config) {
  if (!config.sh_degree_auto || config.fine_iterations == 0 || (config.field_heads & S4D_DEFORM_HEAD_SH) == 0)
    return nullptr;
  config.sh_degree_auto = false;
  std::cerr << "SH degree " << config.sh_degree << " kept: the deformation field's sh head deforms every coefficient\n";
  return {{"degree", config.sh_degree},
          {"why", "kept: the deformation field's sh head deforms all 16 degree-3 coefficients (field_heads includes dsh)"}};
}

}  // namespace s4d::train
