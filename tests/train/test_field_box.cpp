// The deformation field's box fitted to what moves (field_box.h): which Gaussians count as moving,
// the box their paths give, and when the box stays; the time axis their paths need.
#include <array>
#include <cmath>
#include <cstdint>
#include <random>
#include <stdexcept>
#include <vector>

#include <doctest/doctest.h>

#include "s4d/run/train_config.h"
#include "s4d/train/field_box.h"

using namespace s4d;

namespace {

// Paths (lowest and highest mean over time) of Gaussians in the box [-10, 10]^3.
struct Paths {
  std::vector<float> lo, hi;
  void add(std::array<float, 3> from, std::array<float, 3> to) {
    for (int k = 0; k < 3; ++k) lo.push_back(std::min(from[k], to[k])), hi.push_back(std::max(from[k], to[k]));
  }
};

const std::array<float, 3> kMin{-10, -10, -10}, kMax{10, 10, 10};
// 161 texels over 20: cells of 0.125, so the least size (4 cells) is 0.5.
const std::array<uint32_t, 3> kFine{161, 161, 161};

// 500 Gaussians standing still all over the box, and `moving` sliding along x from 1 to 3 at
// y, z in [-1, 1].
Paths scene(uint32_t moving, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> anywhere(-10, 10), near(-1, 1);
  Paths p;
  for (int i = 0; i < 500; ++i) {
    const std::array<float, 3> x{anywhere(rng), anywhere(rng), anywhere(rng)};
    p.add(x, x);
  }
  for (uint32_t i = 0; i < moving; ++i) {
    const float y = near(rng), z = near(rng);
    p.add({1, y, z}, {3, y, z});
  }
  return p;
}

}  // namespace

TEST_CASE("the box shrinks to the moving Gaussians' paths, padded, and ignores what stands still") {
  const Paths p = scene(400, 1);
  const train::FieldBox box = train::fit_field_box(p.lo, p.hi, kMin, kMax, kFine, 0.1);
  REQUIRE(box.fitted);
  CHECK(box.gaussians == 900);
  CHECK(box.moving == 400);
  // x: the paths span [1, 3], padded by a tenth on each side; y and z about [-1, 1] padded.
  CHECK(box.min[0] == doctest::Approx(1 - 0.2));
  CHECK(box.max[0] == doctest::Approx(3 + 0.2));
  for (int k = 1; k < 3; ++k) {
    CHECK(box.min[k] == doctest::Approx(-1.2).epsilon(0.03));
    CHECK(box.max[k] == doctest::Approx(1.2).epsilon(0.03));
  }
  CHECK(box.volume_share == doctest::Approx(2.4 * 2.4 * 2.4 / 8000).epsilon(0.05));
  CHECK(box.old_min == kMin);
  // x: 2.4 in cells of 0.125 is 19.2 cells, so 21 texels, with cells no larger than before.
  CHECK(box.old_resolution == kFine);
  CHECK(box.resolution[0] == 21);
  for (int k = 0; k < 3; ++k) CHECK(double(box.max[k] - box.min[k]) / (box.resolution[k] - 1) <= 0.125 + 1e-6);
  CHECK(box.json()["fitted"] == true);
}

TEST_CASE("a few floaters thrown far do not stretch the box; an axis the motion does not span keeps the least size") {
  Paths p = scene(400, 2);
  for (int i = 0; i < 3; ++i) p.add({-9, -9, -9}, {9, 9, 9});  // under the 1 % quantile of 403
  // z with 11 texels over 20: cells of 2, so the least size is 8.
  const train::FieldBox box = train::fit_field_box(p.lo, p.hi, kMin, kMax, {161, 161, 11}, 0.1);
  REQUIRE(box.fitted);
  CHECK(box.min[0] == doctest::Approx(0.8));
  CHECK(box.max[0] == doctest::Approx(3.2));
  // z spans 2.4 with its pad, under the least size 8: centred on the paths, 8 wide, 5 texels.
  CHECK(box.max[2] - box.min[2] == doctest::Approx(8));
  CHECK(box.resolution[2] == 5);
  CHECK(0.5 * (box.max[2] + box.min[2]) == doctest::Approx(0).epsilon(0.05));

  // The least size near the old box's edge stays inside it.
  Paths edge;
  for (int i = 0; i < 100; ++i) edge.add({9.9f, 0, 0}, {9.9f, 1, 1});
  const train::FieldBox at_edge = train::fit_field_box(edge.lo, edge.hi, kMin, kMax, {21, 21, 21}, 0.1);  // cells of 1
  REQUIRE(at_edge.fitted);
  CHECK(at_edge.max[0] == doctest::Approx(10));
  CHECK(at_edge.min[0] == doctest::Approx(6));
}

TEST_CASE("the box stays when too few Gaussians move or their paths fill it") {
  const Paths few = scene(train::kFieldFitMinMoving - 1, 3);
  const train::FieldBox a = train::fit_field_box(few.lo, few.hi, kMin, kMax, kFine, 0.1);
  CHECK_FALSE(a.fitted);
  CHECK(a.min == kMin);
  CHECK(a.max == kMax);
  CHECK(a.resolution == kFine);
  CHECK(a.why.find("too few") != std::string::npos);

  // Everything moves across most of the box.
  Paths wide;
  for (int i = 0; i < 100; ++i) wide.add({-9.5f, -9.5f, -9.5f}, {9.5f, 9.5f, 9.5f});
  const train::FieldBox b = train::fit_field_box(wide.lo, wide.hi, kMin, kMax, kFine, 0.1);
  CHECK_FALSE(b.fitted);
  CHECK(b.volume_share > train::kFieldFitMaxVolumeShare);
  CHECK(b.max == kMax);
  CHECK(b.why.find("fill") != std::string::npos);

  // A path shorter than the limit is not motion: the 400 sliding Gaussians move 2, under 2.5.
  const Paths p = scene(400, 4);
  CHECK(train::fit_field_box(p.lo, p.hi, kMin, kMax, kFine, 2.5).moving == 0);
  CHECK_THROWS_AS(train::fit_field_box(std::vector<float>(6), std::vector<float>(3), kMin, kMax, kFine, 0.1),
                  std::invalid_argument);
}

TEST_CASE("the fit's step: field_fit of the fine stage once its time window is open, never with field_fit 0 or no fine stage") {
  run::TrainConfig c = run::preset_config("fast");
  CHECK(c.field_fit == doctest::Approx(0.2));
  CHECK(c.fine_time_ramp == doctest::Approx(0.6));
  CHECK(train::field_fit_step(c) == 1020);  // the window opens at 900 of 1500, then 0.2 x the 600 left
  c.fine_time_ramp = 0;  // every time from the start: a fifth of the stage
  CHECK(train::field_fit_step(c) == 300);
  c.fine_iterations = 3;
  CHECK(train::field_fit_step(c) == 1);
  c.field_fit = 0;
  CHECK(train::field_fit_step(c) == 0);
  c.field_fit = 0.5, c.fine_iterations = 0;
  CHECK(train::field_fit_step(c) == 0);
  // Runs from before the fit existed have no field_fit in run.json: off.
  CHECK(run::TrainConfig{}.field_fit == 0);
}

namespace {

// Paths over `samples` evenly spaced times in [0, 1] of `count` Gaussians, each at `x(t)` (the
// same motion along x, offset by the Gaussian's index along y), laid out as fit_field_time reads.
template <class F>
std::vector<float> time_paths(uint32_t samples, uint32_t count, F x) {
  std::vector<float> p;
  for (uint32_t s = 0; s < samples; ++s)
    for (uint32_t i = 0; i < count; ++i) {
      const double t = double(s) / (samples - 1);
      p.insert(p.end(), {static_cast<float>(x(t, i)), float(i), 0.0f});
    }
  return p;
}

// A path from 0 up to 1 at time `knee`, then back to 0 at time 1: piecewise linear, exactly what
// texels at every multiple of `knee` follow.
double kinked(double t, double knee) { return t <= knee ? t / knee : (1 - t) / (1 - knee); }

}  // namespace

// A time axis over the times views have, and 4DGaussians' [-1, 1] of which they reach the upper half.
const std::array<float, 2> kData{0, 1}, kWhole{-1, 1};

TEST_CASE("the time axis: the fewest texels whose piecewise-linear paths follow the sampled ones") {
  const uint32_t texels = 16, samples = 61;  // four samples per texel interval, as the trainer takes
  const std::vector<uint8_t> all(200, 1);
  // Linear motion: the fewest texels the kernels allow.
  train::FieldTime linear = train::fit_field_time(time_paths(samples, 200, [](double t, uint32_t) { return 2 * t; }), samples, 3,
                                                  all, texels, kData, 0.01);
  CHECK(linear.fitted);
  CHECK(linear.resolution == S4D_DEFORM_MIN_RESOLUTION);
  CHECK(linear.moving == 200);
  CHECK(linear.error_by_resolution["3"].get<double>() < 1e-6);
  // A turn at t = 1/3 needs a texel there: 4 texels (0, 1/3, 2/3, 1); 3 (0, 1/2, 1) miss it by half.
  train::FieldTime third = train::fit_field_time(time_paths(samples, 200, [](double t, uint32_t) { return kinked(t, 1.0 / 3); }),
                                                 samples, 3, all, texels, kData, 0.01);
  CHECK(third.resolution == 4);
  CHECK(third.error_by_resolution["3"].get<double>() == doctest::Approx(0.5));  // at t = 1/3: 1, against the line's 0.5
  CHECK(third.error_by_resolution["4"].get<double>() < 1e-6);
  // A turn at t = 1/4: 5 texels.
  CHECK(train::fit_field_time(time_paths(samples, 200, [](double t, uint32_t) { return kinked(t, 0.25); }), samples, 3, all,
                              texels, kData, 0.01)
            .resolution == 5);
  // A tolerance as large as the miss takes the coarser axis.
  CHECK(train::fit_field_time(time_paths(samples, 200, [](double t, uint32_t) { return kinked(t, 1.0 / 3); }), samples, 3, all,
                              texels, kData, 0.6)
            .resolution == 3);
}

TEST_CASE("the time axis over [-1, 1]: texels at times no view has continue the line of the first that has") {
  const uint32_t texels = 16, samples = 61;
  const std::vector<uint8_t> all(200, 1);
  auto fit = [&](auto path) { return train::fit_field_time(time_paths(samples, 200, path), samples, 3, all, texels, kWhole, 0.01); };
  // 3 texels at -1, 0, 1: the times [0, 1] lie between the last two, so a line needs no more.
  CHECK(fit([](double t, uint32_t) { return 2 * t; }).resolution == 3);
  // 4 texels at -1, -1/3, 1/3, 1: [0, 1/3] continues the line from -1/3, so a turn at 1/3 needs no more.
  CHECK(fit([](double t, uint32_t) { return kinked(t, 1.0 / 3); }).resolution == 4);
  // A turn at 1/2 needs a texel there: 5 (-1, -1/2, 0, 1/2, 1).
  const train::FieldTime half = fit([](double t, uint32_t) { return kinked(t, 0.5); });
  CHECK(half.resolution == 5);
  CHECK(half.error_by_resolution["4"].get<double>() == doctest::Approx(0.5));  // at t = 1/2: 1, where the line from 1/3 (2/3) to 1 (0) gives 0.5
  // 9 samples over [0, 1] are two per texel interval up to 9 texels over [-1, 1] (4 intervals in
  // [0, 1]): 7 candidates, none of which follows a path alternating at every sample.
  auto alternating = [](double t, uint32_t) { return double(std::lround(t * 8) % 2); };
  CHECK(train::fit_field_time(time_paths(9, 200, alternating), 9, 3, all, texels, kWhole, 0.01).error_by_resolution.size() == 7);
  CHECK_THROWS_AS(train::fit_field_time(time_paths(9, 200, alternating), 9, 3, all, texels, {1, 1}, 0.01), std::invalid_argument);
}

TEST_CASE("the time axis stays where the paths need most of its texels, or too few Gaussians move") {
  const uint32_t texels = 16, samples = 61;
  const std::vector<uint8_t> all(200, 1);
  // A zigzag turning at every texel: every candidate misses it, and the axis stays.
  auto zigzag = [&](double t, uint32_t) { return std::abs(std::fmod(t * (texels - 1), 2.0) - 1.0); };
  train::FieldTime fast = train::fit_field_time(time_paths(samples, 200, zigzag), samples, 3, all, texels, kData, 0.01);
  CHECK_FALSE(fast.fitted);
  CHECK(fast.resolution == texels);
  CHECK(fast.error_by_resolution.size() == texels - S4D_DEFORM_MIN_RESOLUTION);
  // A turn at t = 1/12 needs 13 texels: more than 70 % of 16, so the axis stays.
  CHECK_FALSE(train::fit_field_time(time_paths(samples, 200, [](double t, uint32_t) { return kinked(t, 1.0 / 12); }), samples, 3,
                                    all, texels, kData, 0.01)
                  .fitted);
  // One zigzag in two hundred does not hold the rest back (the 99th percentile).
  auto mixed = [&](double t, uint32_t i) { return i < 1 ? zigzag(t, i) : 2 * t; };
  CHECK(train::fit_field_time(time_paths(samples, 200, mixed), samples, 3, all, texels, kData, 0.01).resolution ==
        S4D_DEFORM_MIN_RESOLUTION);
  // Only the Gaussians flagged moving count: 10 are too few to say how fast.
  std::vector<uint8_t> few(200, 0);
  for (int i = 0; i < 10; ++i) few[i] = 1;
  train::FieldTime still = train::fit_field_time(time_paths(samples, 200, zigzag), samples, 3, few, texels, kData, 0.01);
  CHECK_FALSE(still.fitted);
  CHECK(still.moving == 10);
  CHECK(still.resolution == texels);
  CHECK_THROWS_AS(train::fit_field_time(std::vector<float>(10), samples, 3, all, texels, kData, 0.01), std::invalid_argument);
  CHECK_THROWS_AS(train::fit_field_time(std::vector<float>(6), 1, 3, std::vector<uint8_t>(2, 1), texels, kData, 0.01), std::invalid_argument);
  // Few samples bound the candidates: 9 samples over 16 texels show at most 5 (two samples per interval).
  auto alternating = [](double t, uint32_t) { return double(std::lround(t * 8) % 2); };  // 0, 1, 0, ... at the samples
  CHECK(train::fit_field_time(time_paths(9, 200, alternating), 9, 3, all, texels, kData, 0.01).error_by_resolution.size() == 3);
}
