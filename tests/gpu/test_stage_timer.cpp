// The stage timer (engine/include/s4d/engine/stage_timer.h): GPU timestamps and the host clock charge
// each scope's work to its stage, nothing outside a window counts, and the stages never add up to
// more than the windows' wall time.
#include <doctest/doctest.h>

#include <stdexcept>

#include "s4d/engine/buffer.h"
#include "s4d/engine/recorder.h"
#include "s4d/engine/stage_timer.h"
#include "s4d/primitives/iota.h"
#include "test_context.h"

using namespace s4d;
using engine::StageScope;
using engine::StageTimer;

namespace {

constexpr uint32_t kWords = 1 << 20;  // an iota over 4 MiB: a few ms on lavapipe

// Slack for the stages' sum against the windows' host wall time: GPU timestamps and the host clock
// are different clocks read at different moments. Measured on lavapipe: the sum stays 3-10 % below
// the wall time (host waits and recording are not in any stage); 1 % + 0.5 ms covers clock
// granularity.
bool within_window(const engine::StageTotals& t) { return t.stage_sum_ms() <= t.window_ms * 1.01 + 0.5; }

// Two stages in one command buffer and one in its own, inside a window; then more work outside it.
engine::StageTotals measure(StageTimer::Clock clock) {
  auto& ctx = test::context();
  engine::Buffer buf(ctx, "stage timer iota", kWords * 4);
  StageTimer timer(ctx, {"first", "second", "unused"}, clock);
  {
    StageTimer::Window window(&timer);
    engine::Recorder rec(ctx, "two stages");
    {
      StageScope s(ctx, "first");
      primitives::cmd_iota(rec, buf, kWords);
      rec.barrier();
    }
    {
      StageScope s(ctx, "second");
      primitives::cmd_iota(rec, buf, kWords);
      rec.barrier();
      StageScope inner(ctx, "added");  // a stage the timer was not given
      primitives::cmd_iota(rec, buf, kWords);
      ctx.run(std::move(rec));
    }
    engine::Recorder other(ctx, "outside every scope");
    primitives::cmd_iota(other, buf, kWords);
    ctx.run(std::move(other));
  }
  const engine::StageTotals in_window = timer.totals();
  {
    StageScope s(ctx, "first");  // no window open: not measured
    engine::Recorder rec(ctx, "after the window");
    primitives::cmd_iota(rec, buf, kWords);
    ctx.run(std::move(rec));
  }
  const engine::StageTotals after = timer.totals();
  CHECK(after.ms == in_window.ms);
  CHECK(after.window_ms == in_window.window_ms);
  return in_window;
}

}  // namespace

TEST_CASE("GPU timestamps charge each scope's commands to its stage") {
  if (!test::context().info().timestamps) return;
  const engine::StageTotals t = measure(StageTimer::Clock::automatic);
  CHECK(t.gpu);
  REQUIRE(t.stages == std::vector<std::string>{"first", "second", "unused", "added"});
  CHECK(t.ms[0] > 0);
  CHECK(t.ms[1] > 0);
  CHECK(t.ms[2] == 0);
  CHECK(t.ms[3] > 0);
  CHECK(t.other_ms > 0);
  CHECK(t.windows == 1);
  CHECK(within_window(t));
}

TEST_CASE("the host clock charges each scope's wall time to its stage") {
  const engine::StageTotals t = measure(StageTimer::Clock::host);
  CHECK_FALSE(t.gpu);
  REQUIRE(t.stages.size() == 4);
  CHECK(t.ms[0] < t.ms[3]);  // only recorded there: submitted and waited for in "added"
  CHECK(t.ms[2] == 0);
  CHECK(t.ms[3] > 0);
  CHECK(t.other_ms > 0);
  CHECK(within_window(t));
}

TEST_CASE("totals add stage by stage name") {
  engine::StageTotals a{.gpu = true, .stages = {"x", "y"}, .ms = {1, 2}, .other_ms = 0.5, .window_ms = 4, .windows = 1};
  const engine::StageTotals b{.gpu = true, .stages = {"y", "z"}, .ms = {10, 20}, .other_ms = 1, .window_ms = 40, .windows = 2};
  a += b;
  CHECK(a.stages == std::vector<std::string>{"x", "y", "z"});
  CHECK(a.ms == std::vector<double>{1, 12, 20});
  CHECK(a.stage_sum_ms() == 34.5);
  CHECK(a.window_ms == 44);
  CHECK(a.windows == 3);
  engine::StageTotals host{.gpu = false, .stages = {}, .ms = {}, .other_ms = 0, .window_ms = 1, .windows = 1};
  CHECK_THROWS_AS(host += b, std::logic_error);
}

TEST_CASE("a recorder dropped unsubmitted gives its queries back; one timer per context") {
  auto& ctx = test::context();
  engine::Buffer buf(ctx, "stage timer iota", 1024);
  StageTimer timer(ctx, {"a"});
  CHECK_THROWS_AS(StageTimer(ctx, {"b"}), std::logic_error);
  StageTimer::Window window(&timer);
  StageScope s(ctx, "a");
  for (int i = 0; i < 200; ++i) {  // more timestamps than one query pool holds, were none given back
    engine::Recorder rec(ctx, "dropped");
    primitives::cmd_iota(rec, buf, 256);
  }
  engine::Recorder rec(ctx, "kept");
  primitives::cmd_iota(rec, buf, 256);
  ctx.run(std::move(rec));
  CHECK(timer.totals().ms[0] > 0);
  CHECK(timer.query_pools() == (ctx.info().timestamps ? 1u : 0u));
}

TEST_CASE("a submission still running when an earlier one is waited for keeps its timestamps") {
  auto& ctx = test::context();
  if (!ctx.info().timestamps) return;  // only GPU timestamps wait for completion
  engine::Buffer buf(ctx, "stage timer iota", kWords * 4);
  StageTimer timer(ctx, {"first", "second"});
  StageTimer::Window window(&timer);
  auto submit = [&](const char* stage) {
    const StageScope s(ctx, stage);
    engine::Recorder rec(ctx, stage);
    primitives::cmd_iota(rec, buf, kWords);
    return ctx.submit(std::move(rec));
  };
  ctx.wait(submit("first"));
  submit("second");  // not waited for: the only one pending when the wait below collects
  ctx.wait(1);
  const engine::StageTotals t = timer.totals();
  CHECK(t.ms[0] > 0);
  CHECK(t.ms[1] > 0);  // 0 when the pending entry was moved onto itself (its marks emptied)
}
