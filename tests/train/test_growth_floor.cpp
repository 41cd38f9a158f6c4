// growth_floor.h: how far the densification threshold drops for a cloud far below its budget.
#include <doctest/doctest.h>

#include <cmath>

#include "s4d/densify/growth_floor.h"

using namespace s4d;

TEST_CASE("growth share: enough densifying Gaussians to reach the budget in the events left") {
  CHECK(densify::growth_share(1000, 16000, 4) == doctest::Approx(1.0));  // 2x per event: everyone
  CHECK(densify::growth_share(1000, 8000, 3) == doctest::Approx(1.0));
  CHECK(densify::growth_share(1000, 8000, 6) == doctest::Approx(std::sqrt(2.0) - 1));  // 8 = sqrt(2)^6
  CHECK(densify::growth_share(100, 1'000'000, 1) == 1.0);                // capped: a Gaussian adds at most one
  // From a quarter of the budget on, or with no event left, graphdeco's threshold alone decides.
  CHECK(densify::growth_share(4000, 16000, 4) == 0.0);
  CHECK(densify::growth_share(3999, 16000, 4) > 0.0);
  CHECK(densify::growth_share(100, 16000, 0) == 0.0);
  CHECK(densify::growth_share(0, 16000, 3) == 0.0);
}

TEST_CASE("threshold for a share: the k-th largest mean gradient of the seen Gaussians, never above graphdeco's") {
  // Means 0.4, 0.1, unseen, 0.3, 0.2 (accum / count).
  const std::vector<float> accum = {0.8f, 0.1f, 5.0f, 0.9f, 0.4f}, count = {2, 1, 0, 3, 2};
  CHECK(densify::threshold_for_share(accum, count, 0.25, 1.0f) == doctest::Approx(0.4f));  // 1 of 4 seen
  CHECK(densify::threshold_for_share(accum, count, 0.5, 1.0f) == doctest::Approx(0.3f));   // 2 of 4
  CHECK(densify::threshold_for_share(accum, count, 0.6, 1.0f) == doctest::Approx(0.2f));   // ceil(2.4) = 3
  CHECK(densify::threshold_for_share(accum, count, 1.0, 1.0f) == doctest::Approx(0.1f));   // all seen; the unseen never
  CHECK(densify::threshold_for_share(accum, count, 1.0, 0.05f) == 0.05f);  // graphdeco's already lets them all through
  CHECK(densify::threshold_for_share(accum, count, 0.0, 0.25f) == 0.25f);
  CHECK(densify::threshold_for_share({1.0f}, {0.0f}, 1.0, 0.25f) == 0.25f);  // nothing seen
}
