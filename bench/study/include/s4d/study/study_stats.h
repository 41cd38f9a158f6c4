// The statistics of the study report: confidence intervals of vote shares, Bradley-Terry scores
// from pairwise wins, and Krippendorff's alpha between raters.
#pragma once
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace s4d::study {

// The Wilson score interval of a proportion wins / n at 95 % (z = 1.959964): unlike the normal
// approximation it stays inside [0, 1] and is usable at small n and shares near 0 or 1. n = 0 gives
// [0, 1].
struct Interval {
  double low = 0, high = 1;
};
Interval wilson_interval(int wins, int n);

// Bradley-Terry strengths p (P(i beats j) = p_i / (p_i + p_j)), normalised to sum to 1, fitted by
// Hunter's (2004) MM iteration p_i <- W_i / sum_j n_ij / (p_i + p_j) to a relative change of 1e-12.
// wins[i][j]: times i beat j. The maximum-likelihood fit exists only when every split of the methods
// into two groups has a win each way; otherwise `why` says which method has no win against the rest.
struct BradleyTerry {
  std::vector<double> strength;  // empty when unavailable
  std::string why;
  int iterations = 0;
};
BradleyTerry bradley_terry(const std::vector<std::vector<int>>& wins, const std::vector<std::string>& names);

// Krippendorff's alpha for nominal data: units[u] holds the values the raters gave unit u (missing
// ratings simply absent). Units with fewer than two values are not pairable and are left out.
// alpha = 1 - (n - 1) * sum_{c != k} o_ck / sum_{c != k} n_c n_k over the coincidence matrix o.
// Nothing when no unit is pairable or every pairable value is the same (no expected disagreement).
std::optional<double> krippendorff_alpha_nominal(const std::vector<std::vector<std::string>>& units);

}  // namespace s4d::study
