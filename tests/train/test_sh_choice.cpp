// The SH degree chosen from the data (sh_choice.h): which degree the held-out PSNRs keep, when the
// choice is made, and the state cut to the chosen degree.
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <doctest/doctest.h>

#include "host_state_fixture.h"
#include "s4d/run/train_config.h"
#include "s4d/train/sh_choice.h"
#include "s4d/train/split_state.h"

using namespace s4d;

TEST_CASE("the lowest degree within kShKeepDb of the top degree's held-out PSNR is kept") {
  const double keep = train::kShKeepDb;
  CHECK(train::lowest_sufficient_degree(std::vector<double>{25.0, 25.0 + 0.9 * keep}) == 0);
  CHECK(train::lowest_sufficient_degree(std::vector<double>{25.0, 25.0 + 1.1 * keep}) == 1);
  CHECK(train::lowest_sufficient_degree(std::vector<double>{25.3, 25.0}) == 0);  // the top degree hurts: dropped
  CHECK(train::lowest_sufficient_degree(std::vector<double>{24.0, 25.0, 25.0 + 0.5 * keep, 25.0 + 0.9 * keep}) == 1);
  CHECK(train::lowest_sufficient_degree(std::vector<double>{24.0, 25.0, 26.0, 27.0}) == 3);
  CHECK(train::lowest_sufficient_degree(std::vector<double>{30.0}) == 0);
  CHECK_THROWS_AS(train::lowest_sufficient_degree(std::vector<double>{}), std::invalid_argument);
  CHECK_THROWS_AS(train::lowest_sufficient_degree(std::vector<double>{25.0, std::nan("")}), std::invalid_argument);
  CHECK_THROWS_AS(train::lowest_sufficient_degree(std::vector<double>{25.0, std::numeric_limits<double>::infinity()}),
                  std::invalid_argument);
}

TEST_CASE("the choice comes once the top degree has trained for sh_up_every steps, or at the run's end") {
  run::TrainConfig c = run::preset_config("fast");  // degree 1 from step 300; 900 + 1500 steps
  CHECK(c.sh_degree_auto);
  CHECK(train::sh_choice_step(c) == 600);
  c = run::preset_config("default");  // degree 3 from step 3000 (4DGaussians'): in the 4DGS stage
  CHECK(train::sh_choice_step(c) == 4000);
  c.fine_iterations = 0, c.iterations = 2500;  // ends before degree 3 has trained: at the end
  CHECK(train::sh_choice_step(c) == 2500);
  CHECK_FALSE(run::TrainConfig{}.sh_degree_auto);  // runs from before the choice keep their degree
}

TEST_CASE("cutting the SH to a lower degree keeps each Gaussian's first coefficients and their moments") {
  const model::HostState s = test::small_state(5, 2, 7);  // 9 coefficients, 27 floats per Gaussian
  const model::HostState r = train::with_sh_degree(s, 1);  // 4 coefficients, 12 floats
  const splat::Attr sh = splat::Attr::sh;
  REQUIRE(r.cloud.sh_degree == 1);
  REQUIRE(r.cloud.size() == 5);
  REQUIRE(r.cloud.sh.size() == 5 * 12);
  REQUIRE(r.m[sh].size() == 5 * 12);
  REQUIRE(r.v[sh].size() == 5 * 12);
  for (size_t g = 0; g < 5; ++g)
    for (size_t f = 0; f < 12; ++f) {
      CHECK(r.cloud.sh[g * 12 + f] == s.cloud.sh[g * 27 + f]);
      CHECK(r.m[sh][g * 12 + f] == s.m[sh][g * 27 + f]);
      CHECK(r.v[sh][g * 12 + f] == s.v[sh][g * 27 + f]);
    }
  CHECK(r.cloud.means == s.cloud.means);
  CHECK(r.m[splat::Attr::quats] == s.m[splat::Attr::quats]);
  CHECK(r.stats[model::kMaxRadius] == s.stats[model::kMaxRadius]);
  CHECK(train::with_sh_degree(s, 0).cloud.sh.size() == 5 * 3);
  CHECK(train::with_sh_degree(s, 2).cloud.sh == s.cloud.sh);
  CHECK_THROWS_AS(train::with_sh_degree(s, 3), std::invalid_argument);
  CHECK_THROWS_AS(train::with_sh_degree(s, -1), std::invalid_argument);
}

TEST_CASE("a field whose sh head deforms every coefficient keeps the degree, decided when the run starts") {
  run::TrainConfig c = run::preset_config("default");  // 4DGaussians' DyNeRF heads: dx ds dr do dsh
  const nlohmann::json kept = train::keep_sh_for_field(c);
  REQUIRE(kept.is_object());
  CHECK(kept["degree"] == 3);
  CHECK(kept["why"].get<std::string>().starts_with("kept: the deformation field's sh head"));
  CHECK_FALSE(c.sh_degree_auto);
  run::TrainConfig fast = run::preset_config("fast");  // dx ds dr: the choice stays on
  CHECK(train::keep_sh_for_field(fast).is_null());
  CHECK(fast.sh_degree_auto);
  run::TrainConfig still = run::preset_config("default");
  still.fine_iterations = 0;  // no field at all
  CHECK(train::keep_sh_for_field(still).is_null());
  CHECK(still.sh_degree_auto);
}
