// IRLS aggregation on hand-built cases where the answer is known.
#include <doctest/doctest.h>

#include "s4d/frame_stylizers/robust_aggregation.h"

using namespace s4d;

TEST_CASE("robust aggregation rejects an outlier patch that plain averaging keeps") {
  // Three 1x1 patches on the same pixel: two say 0, one says 1. The mean is 1/3; the r = 0.8 norm's
  // minimiser is 0, which IRLS approaches geometrically (about 0.18, 0.075, 0.03, ... from 1/3).
  const io::ImageF current{1, 1, 1, {1.0f / 3.0f}};
  const float zero = 0.0f, one = 1.0f;
  const std::vector<frame_stylizers::PlacedPatch> patches = {{0, 0, &zero}, {0, 0, &zero}, {0, 0, &one}};
  const io::ImageF robust = frame_stylizers::robust_aggregate(current, 1, patches, {0.8f, 10, 1e-3f});
  CHECK(robust.data[0] < 1e-3f);  // 1.3e-4 after these 10 steps (the same arithmetic in double)
  const io::ImageF least_squares = frame_stylizers::robust_aggregate(current, 1, patches, {2.0f, 3, 1e-3f});
  CHECK(least_squares.data[0] == doctest::Approx(1.0 / 3.0).epsilon(1e-6));  // r = 2 is the plain mean
}

TEST_CASE("agreeing patches are reproduced and uncovered pixels keep their values") {
  // A 4x3 RGB image, two overlapping 2x2 patches cut from one target: the overlap agrees.
  io::ImageF current{4, 3, 3, std::vector<float>(36, 0.25f)};
  std::vector<float> target(36);
  for (size_t i = 0; i < target.size(); ++i) target[i] = 0.02f * static_cast<float>(i);
  auto cut = [&](int x, int y) {
    std::vector<float> p;
    for (int dy = 0; dy < 2; ++dy)
      for (int dx = 0; dx < 2; ++dx)
        for (int c = 0; c < 3; ++c) p.push_back(target[((y + dy) * 4 + x + dx) * 3 + c]);
    return p;
  };
  const std::vector<float> a = cut(0, 0), b = cut(1, 0);
  const io::ImageF out = frame_stylizers::robust_aggregate(current, 2, {{0, 0, a.data()}, {1, 0, b.data()}}, {});
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 4; ++x)
      for (int c = 0; c < 3; ++c) {
        const size_t i = static_cast<size_t>((y * 4 + x) * 3 + c);
        const bool covered = y < 2 && x < 3;
        CAPTURE(i);
        CHECK(out.data[i] == doctest::Approx(covered ? target[i] : 0.25f).epsilon(1e-6));
      }
}

TEST_CASE("robust aggregation refuses patches outside the image") {
  const io::ImageF current{2, 2, 1, std::vector<float>(4, 0.0f)};
  const std::vector<float> p(4, 1.0f);
  CHECK_THROWS_AS(frame_stylizers::robust_aggregate(current, 2, {{1, 0, p.data()}}, {}), std::invalid_argument);
  CHECK_THROWS_AS(frame_stylizers::robust_aggregate(current, 2, {{0, 0, nullptr}}, {}), std::invalid_argument);
}
