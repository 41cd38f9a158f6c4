// The study report's statistics against values computed independently: Wilson intervals by the
// textbook formula, Bradley-Terry by Newton's method on the log-likelihood (not the MM iteration
// the report uses) and in closed form for two methods, Krippendorff's alpha on the nominal example
// of Krippendorff's "Computing Krippendorff's Alpha-Reliability" (2011), published as 0.743. The
// reference values were computed in pure Python: see the comments by each.
#include <doctest/doctest.h>

#include "s4d/study/study_stats.h"

using namespace s4d::study;

TEST_CASE("Wilson score interval") {
  // (p + z^2/2n) / (1 + z^2/n) -/+ z / (1 + z^2/n) sqrt(p (1 - p) / n + z^2 / 4n^2), z = 1.959964.
  const Interval a = wilson_interval(8, 10);
  CHECK(a.low == doctest::Approx(0.4901624715366418).epsilon(1e-12));
  CHECK(a.high == doctest::Approx(0.9433178485456248).epsilon(1e-12));
  const Interval b = wilson_interval(0, 5);  // stays inside [0, 1], unlike the normal approximation
  CHECK(b.low == 0.0);
  CHECK(b.high == doctest::Approx(0.43448246478317476).epsilon(1e-12));
  const Interval c = wilson_interval(17, 34);  // symmetric about one half
  CHECK(c.low == doctest::Approx(0.340693256456825).epsilon(1e-12));
  CHECK(c.high == doctest::Approx(0.659306743543175).epsilon(1e-12));
  const Interval none = wilson_interval(0, 0);
  CHECK(none.low == 0.0);
  CHECK(none.high == 1.0);
}

TEST_CASE("Bradley-Terry by the MM iteration") {
  // Two methods: the fit is p_A / p_B = wins_A / wins_B exactly.
  const BradleyTerry two = bradley_terry({{0, 3}, {1, 0}}, {"A", "B"});
  REQUIRE(two.strength.size() == 2);
  CHECK(two.strength[0] == doctest::Approx(0.75).epsilon(1e-10));
  CHECK(two.strength[1] == doctest::Approx(0.25).epsilon(1e-10));
  // Three methods, wins[i][j] = times i beat j; Newton's method on log-strengths gives
  // 0.5268784816535887, 0.24904762841527758, 0.22407388993113378 (normalised to sum 1).
  const BradleyTerry three = bradley_terry({{0, 7, 4}, {3, 0, 6}, {2, 5, 0}}, {"A", "B", "C"});
  REQUIRE(three.strength.size() == 3);
  CHECK(three.strength[0] == doctest::Approx(0.5268784816535887).epsilon(1e-9));
  CHECK(three.strength[1] == doctest::Approx(0.24904762841527758).epsilon(1e-9));
  CHECK(three.strength[2] == doctest::Approx(0.22407388993113378).epsilon(1e-9));
  // A method that never wins has strength 0 at the supremum: no maximum-likelihood fit, said by name.
  const BradleyTerry lost = bradley_terry({{0, 2, 1}, {1, 0, 3}, {0, 0, 0}}, {"A", "B", "C"});
  CHECK(lost.strength.empty());
  CHECK(lost.why.find("C never beats") != std::string::npos);
  // Two groups never compared with each other.
  const BradleyTerry apart = bradley_terry({{0, 1, 0, 0}, {1, 0, 0, 0}, {0, 0, 0, 2}, {0, 0, 2, 0}}, {"A", "B", "C", "D"});
  CHECK(apart.strength.empty());
}

TEST_CASE("Krippendorff's alpha, nominal") {
  // Krippendorff (2011), the example with 4 observers, 12 units and missing values (rows are units
  // here; absent ratings left out). Published nominal alpha: 0.743; pairwise formula in Python:
  // 0.743421052631579.
  const std::vector<std::vector<std::string>> units = {
      {"1", "1", "1"}, {"2", "2", "3", "2"}, {"3", "3", "3", "3"}, {"3", "3", "3", "3"}, {"2", "2", "2", "2"},
      {"1", "2", "3", "4"}, {"4", "4", "4", "4"}, {"1", "1", "2", "1"}, {"2", "2", "2", "2"}, {"5", "5", "5"},
      {"1", "1"}, {"3"}};
  const std::optional<double> alpha = krippendorff_alpha_nominal(units);
  REQUIRE(alpha);
  CHECK(*alpha == doctest::Approx(0.743421052631579).epsilon(1e-12));
  // Full agreement on varied values: 1. Raters who always disagree in pairs: below 0.
  CHECK(*krippendorff_alpha_nominal({{"a", "a"}, {"b", "b"}, {"a", "a"}}) == doctest::Approx(1.0));
  CHECK(*krippendorff_alpha_nominal({{"a", "b"}, {"a", "b"}}) < 0.0);
  // One value everywhere, or nothing pairable: undefined.
  CHECK_FALSE(krippendorff_alpha_nominal({{"a", "a"}, {"a", "a", "a"}}));
  CHECK_FALSE(krippendorff_alpha_nominal({{"a"}, {"b"}}));
}
