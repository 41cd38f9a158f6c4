#include "s4d/train/sh_choice.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace s4d::train {

nlohmann::json ShChoice::json() const {
  return {{"degree", degree},
          {"psnr_by_degree", psnr},
          {"keep_db", kShKeepDb},
          {"views", views},
          {"at_step", at_step},
          {"why", "the lowest degree whose held-out PSNR is within keep_db of degree " + std::to_string(psnr.size() - 1) +
                      "'s; the coefficients above it are dropped"}};
}

int lowest_sufficient_degree(std::span<const double> psnr_by_degree) {
  if (psnr_by_degree.empty()) throw std::invalid_argument("lowest_sufficient_degree: no degrees measured");
  for (double p : psnr_by_degree)
    if (!std::isfinite(p)) throw std::invalid_argument("lowest_sufficient_degree: a non-finite PSNR");
  const double top = psnr_by_degree.back();
  for (size_t d = 0; d < psnr_by_degree.size(); ++d)
    if (psnr_by_degree[d] >= top - kShKeepDb) return static_cast<int>(d);
  return static_cast<int>(psnr_by_degree.size() - 1);
}

uint32_t sh_choice_step(const run::TrainConfig& config) {
  const uint64_t after = uint64_t(config.sh_degree + 1) * std::max<uint32_t>(1, config.sh_up_every);
  const uint64_t last = uint64_t(config.iterations) + config.fine_iterations;
  return static_cast<uint32_t>(std::min(after, last));
}

}  // namespace s4d::train
