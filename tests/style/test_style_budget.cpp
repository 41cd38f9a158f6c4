// stylize --time-budget's planning of stage 4 (style_budget.h): the colour-only and MLP phases
// scaled together before the MLPs join, the MLP phase alone after, the caps, and the phase test.
#include <doctest/doctest.h>

#include "s4d/style_gaussians/style_budget.h"
#include "s4d/train/time_budget.h"

using namespace s4d;
using style_gaussians::StyleConfig;

TEST_CASE("style budget: before the MLPs join, one factor scales both phases to the deadline") {
  const StyleConfig start = style_gaussians::style_setting("tuned");  // 1500 steps, the last 300 with MLPs
  // 50 steps done at 5 s, 0.1 s a colour step, an MLP step 3x that: scale f costs
  // (1200 f - 50) 0.1 + 300 f 0.3 = 210 f - 5, so a deadline at 105 s (100 s left) gives f = 0.5.
  const style_gaussians::StyleLengths l = style_gaussians::fitted_style_lengths(start, start, 50, 105, 5, 0.1, 3.0);
  CHECK(l.iterations == 750);
  CHECK(l.mlp_iterations == 150);
  // A deadline already past: the colour phase ends now and the MLPs get one step.
  const style_gaussians::StyleLengths late = style_gaussians::fitted_style_lengths(start, start, 50, 1, 5, 0.1, 3.0);
  CHECK(late.iterations == 51);
  CHECK(late.mlp_iterations == 1);
  // Time to spare: at most kMaxStretch x each phase.
  const style_gaussians::StyleLengths long_ = style_gaussians::fitted_style_lengths(start, start, 50, 1e6, 5, 0.1, 3.0);
  CHECK(long_.iterations == static_cast<uint32_t>(train::kMaxStretch * 1500));
  CHECK(long_.mlp_iterations == static_cast<uint32_t>(train::kMaxStretch * 300));
}

TEST_CASE("style budget: once the MLPs train, only their phase is refitted, from their own step time") {
  const StyleConfig start = style_gaussians::style_setting("tuned");
  StyleConfig current = start;
  current.iterations = 900, current.mlp_iterations = 200;  // an earlier plan: 700 colour steps, then 200
  REQUIRE(style_gaussians::mlp_phase(current, 720));
  // 20 MLP steps done at 100 s, 0.25 s each; 30 s left: 120 more.
  const style_gaussians::StyleLengths l = style_gaussians::fitted_style_lengths(start, current, 720, 130, 100, 0.25, 3.0);
  CHECK(l.iterations == 700 + 140);
  CHECK(l.mlp_iterations == 140);
}

TEST_CASE("style budget: the paper setting trains the MLPs throughout; colours only has one phase") {
  const StyleConfig paper = style_gaussians::style_setting("paper");
  REQUIRE(paper.mlp_iterations == paper.iterations);
  CHECK(style_gaussians::mlp_phase(paper, 0));
  // 40 s left at 0.5 s a step after 100 steps: 180 steps, all with the MLPs.
  const style_gaussians::StyleLengths l = style_gaussians::fitted_style_lengths(paper, paper, 100, 60, 20, 0.5, 3.0);
  CHECK(l.iterations == 180);
  CHECK(l.mlp_iterations == 180);

  StyleConfig colors = style_gaussians::style_setting("tuned");
  colors.method = run::StyleMethod::colors;
  CHECK_FALSE(style_gaussians::mlp_phase(colors, 1499));
  const style_gaussians::StyleLengths c = style_gaussians::fitted_style_lengths(colors, colors, 100, 60, 20, 0.1, 3.0);
  CHECK(c.iterations == 500);
  CHECK(c.mlp_iterations == 300);  // unused by colours only; kept within the length
}

TEST_CASE("style budget: the phase test agrees with the trainer's step count (the step after `done`)") {
  StyleConfig c = style_gaussians::style_setting("tuned");
  CHECK_FALSE(style_gaussians::mlp_phase(c, 1199));  // step 1200 is the last colour-only one
  CHECK(style_gaussians::mlp_phase(c, 1200));        // step 1201 is the first of the last 300
}
