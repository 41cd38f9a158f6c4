// The rasterizer's forward as one command buffer: one submission and one host wait per frame, the
// instance count kept on the device (instance_args.comp and the indirect tile sort), and the
// overflow path: a capacity far below the frame's instances drops instances on the device, then
// finish_forward() grows the buffers and the re-rendered frame is the normal one, bit for bit.
#include <doctest/doctest.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <vector>

#include "s4d/engine/buffer_from.h"
#include "s4d/primitives/shader_pipeline.h"
#include "s4d_primitives.h"
#include "s4d_splat.h"
#include "splat_harness.h"
#include "test_context.h"

namespace {

using namespace s4d;

constexpr std::array<float, 3> kBg = {0.2f, 0.1f, 0.4f};

// Every per-tile and per-instance output of the last forward, downloaded.
struct Lists {
  std::vector<uint32_t> ranges, ids;
};
Lists lists(splat::Rasterizer& r, uint32_t tiles, uint32_t instances) {
  engine::Context& ctx = r.context();
  return {ctx.download<uint32_t>(r.tile_ranges(), 2 * size_t{tiles}), ctx.download<uint32_t>(r.instance_ids(), instances)};
}

}  // namespace

TEST_CASE("a forward is one submission and one host wait once its buffers fit") {
  engine::Context& ctx = test::context();
  std::mt19937 rng(31);
  const test::Cam cam = test::random_camera(90, 70, rng);
  const test::DeviceScene dev(ctx, test::random_scene(1200, 2, false, rng));
  splat::Rasterizer r(ctx, "one submission");
  (void)r.forward(dev.params, test::gpu_camera(cam), kBg);  // sizes every buffer
  const uint32_t overflows = r.overflows();
  const uint64_t submissions = ctx.submissions(), waits = ctx.host_waits();
  const splat::RenderStats stats = r.forward(dev.params, test::gpu_camera(cam), kBg);
  CHECK(stats.instances > 1024);  // past the default first capacity: the first forward grew it
  CHECK(ctx.submissions() - submissions == 1);
  CHECK(ctx.host_waits() - waits == 1);
  CHECK(r.overflows() == overflows);
}

TEST_CASE("a tiny instance capacity overflows once and then renders the normal frame bit for bit") {
  engine::Context& ctx = test::context();
  std::mt19937 rng(32);
  const test::Cam cam = test::random_camera(83, 61, rng);
  const uint32_t tiles = ((83 + 15) / 16) * ((61 + 15) / 16);
  const test::DeviceScene dev(ctx, test::random_scene(1500, 3, false, rng));
  splat::Rasterizer normal(ctx, "normal", {.initial_instance_capacity = 1u << 20});
  splat::Rasterizer tiny(ctx, "tiny", {.initial_instance_capacity = 7});
  const test::GpuForward want = test::gpu_forward(normal, dev, cam, kBg);
  CHECK(normal.overflows() == 0);
  const uint64_t submissions = ctx.submissions();
  const splat::RenderStats first = tiny.forward(dev.params, test::gpu_camera(cam), kBg);
  CHECK(ctx.submissions() - submissions == 2);  // the overflowed frame, then the frame again
  CHECK(tiny.overflows() == 1);
  CHECK(tiny.instance_capacity() >= want.instances);
  CHECK(first.instances == want.instances);
  CHECK(first.longest_tile_list == want.longest_tile_list);
  const test::GpuForward got = test::gpu_forward(tiny, dev, cam, kBg);
  CHECK(tiny.overflows() == 1);  // the grown buffers hold the next frame
  CHECK(got.proj.mean2d == want.proj.mean2d);
  CHECK(got.img.rgb == want.img.rgb);
  CHECK(got.img.alpha == want.img.alpha);
  CHECK(got.img.depth == want.img.depth);
  CHECK(got.img.count == want.img.count);
  const Lists a = lists(tiny, tiles, want.instances), b = lists(normal, tiles, want.instances);
  CHECK(a.ranges == b.ranges);
  CHECK(a.ids == b.ids);
}

// instance_args against the host's split (Recorder::split_groups): the live count clamps to the
// capacity, and each indirect dispatch covers its groups with less than one row of overshoot.
TEST_CASE("instance_args writes the live count and dispatches split as the host splits") {
  engine::Context& ctx = test::context();
  const engine::Pipeline& pipe = primitives::shader_pipeline(ctx, shaders::Id::instance_args);
  for (const uint32_t count : {0u, 1u, 255u, 256u, 257u, 2048u, 2049u, 100000u, 5000000u}) {
    for (const uint32_t capacity : {0u, 300u, 4096u, 6000000u}) {
      for (const uint32_t max_x : {3u, 65535u}) {
        CAPTURE(count);
        CAPTURE(capacity);
        CAPTURE(max_x);
        engine::Buffer offsets = engine::buffer_from(ctx, "offsets", std::vector<uint32_t>{9, 9, count});
        engine::Buffer args = engine::buffer_from(ctx, "args", std::vector<uint32_t>(12, 0xDEAD));
        engine::Recorder rec(ctx, "instance_args");
        rec.dispatch(pipe, {S4D_BIND(ARGS_OFFSETS, offsets), S4D_BIND(ARGS_OUT, args)},
                     gpu::InstanceArgsParams{.n = 2, .capacity = capacity, .max_groups_x = max_x, ._pad0 = 0}, 1);
        ctx.run(std::move(rec));
        const std::vector<uint32_t> got = ctx.download<uint32_t>(args, 12);
        const uint32_t live = std::min(count, capacity);
        CHECK(got[0] == live);
        for (const auto& [offset, per_group] : {std::pair<uint32_t, uint32_t>{S4D_INSTANCE_ARGS_RANGES_OFFSET / 4, S4D_SPLAT_WG},
                                                std::pair<uint32_t, uint32_t>{S4D_INSTANCE_ARGS_SORT_OFFSET / 4, S4D_RADIX_BLOCK}}) {
          const uint64_t groups = (uint64_t{live} + per_group - 1) / per_group;
          const uint64_t x = got[offset], y = got[offset + 1];
          CHECK(got[offset + 2] == 1);
          CHECK(x <= max_x);
          CHECK(x * y >= groups);
          if (groups <= max_x) CHECK((x == groups && y == 1));
          else CHECK(x * y - groups < x);
        }
      }
    }
  }
}
