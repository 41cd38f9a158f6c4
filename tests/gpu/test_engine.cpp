// Engine behaviour on the test device: round trips, the dispatch choke point's checks (binding by
// id included), 2-D dispatch past the group limit, limit errors that name the buffer, timestamps,
// deferred frees.
#include <doctest/doctest.h>

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <stdexcept>
#include <vector>

#include "expect_equal.h"
#include "s4d/engine/buffer.h"
#include "s4d/engine/buffer_from.h"
#include "s4d/engine/pipeline.h"
#include "s4d/engine/recorder.h"
#include "s4d/engine/timestamps.h"
#include "s4d/primitives/iota.h"
#include "s4d/shader_registry.h"
#include "s4d_optim.h"
#include "s4d_primitives.h"
#include "test_context.h"

using namespace s4d;
using engine::Buffer;
using engine::Recorder;

namespace {
const engine::Pipeline& iota_pipeline() {
  const auto& e = shaders::get(shaders::Id::iota);
  return test::context().pipeline(e.name, e.spirv());
}
const engine::Pipeline& add_pipeline() {
  const auto& e = shaders::get(shaders::Id::grad_add);
  return test::context().pipeline(e.name, e.spirv());
}
}  // namespace

TEST_CASE("device info records the features and limits the kernels use") {
  const auto& info = test::context().info();
  CHECK(info.suitable);
  CHECK(info.subgroup_size >= 1);
  CHECK(info.min_subgroup_size <= info.subgroup_size);
  CHECK(info.subgroup_size <= info.max_subgroup_size);
  CHECK(info.max_workgroup_count[0] >= 65535);
  CHECK(info.max_storage_buffer_range >= (1u << 27) - 1);  // Vulkan guarantees 2^27
  CHECK(info.max_push_constant_bytes >= 128);
  CHECK(!info.driver_name.empty());
}

TEST_CASE("upload then download round-trips, at offsets too") {
  auto& ctx = test::context();
  Buffer b(ctx, "roundtrip", 1000 * 4);
  std::vector<uint32_t> data(1000);
  std::iota(data.begin(), data.end(), 7u);
  ctx.upload(b, std::span<const uint32_t>(data));
  test::expect_equal_arrays(ctx.download<uint32_t>(b, 1000), data, "whole buffer");
  std::vector<uint32_t> part = {1, 2, 3};
  ctx.upload(b, std::span<const uint32_t>(part), 500);
  test::expect_equal_arrays(ctx.download<uint32_t>(b, 3, 500), part, "at offset");
  CHECK_THROWS_WITH_AS(ctx.upload(b, std::span<const uint32_t>(data), 1), doctest::Contains("roundtrip"),
                       std::invalid_argument);
}

TEST_CASE("dispatch past 65,535 workgroups runs as a 2-D grid and covers every element") {
  // Capped at llvmpipe's limit, so a device with a far larger one (NVIDIA: 2^31 - 1, where the
  // element count below would overflow) takes the same path.
  engine::ContextOptions options = engine::ContextOptions::from_env();
  options.validation = test::context().validation_enabled();
  options.max_groups_x = 65535;
  engine::Context ctx(options);
  const uint32_t max_x = std::min(65535u, ctx.info().max_workgroup_count[0]);
  const uint32_t n = (max_x + 1000) * S4D_IOTA_WG + 17;
  Buffer out(ctx, "iota 2-D", size_t{n} * 4);
  Recorder rec(ctx, "iota 2-D");
  CHECK(rec.split_groups((n + S4D_IOTA_WG - 1) / S4D_IOTA_WG).y == 2);
  primitives::cmd_iota(rec, out, n, 5);
  ctx.run(std::move(rec));
  const auto got = ctx.download<uint32_t>(out, n);
  size_t bad = 0;
  for (uint32_t i = 0; i < n; ++i) bad += got[i] != i + 5;
  CHECK(bad == 0);
}

TEST_CASE("the dispatch choke point refuses wrong push-constant sizes and ranges, naming the binding") {
  auto& ctx = test::context();
  Buffer a(ctx, "a", 64);
  Recorder rec(ctx, "bad dispatches");
  const gpu::IotaParams params{};
  const uint32_t too_small = 3;
  CHECK_THROWS_WITH_AS(rec.dispatch(iota_pipeline(), {S4D_BIND(IOTA_OUT, a)}, too_small, 1),
                       doctest::Contains("push constants are 4 bytes"), std::invalid_argument);
  CHECK_THROWS_WITH_AS(rec.dispatch(iota_pipeline(), {S4D_BIND(IOTA_OUT, a, 32, 64)}, params, 1),
                       doctest::Contains("S4D_B_IOTA_OUT: range overruns buffer 'a'"), std::invalid_argument);
  if (ctx.info().min_storage_buffer_offset_alignment > 4)
    CHECK_THROWS_WITH_AS(rec.dispatch(iota_pipeline(), {S4D_BIND(IOTA_OUT, a, 4, 16)}, params, 1),
                         doctest::Contains("minStorageBufferOffsetAlignment"), std::invalid_argument);
}

TEST_CASE("an indirect dispatch reads its group counts from a buffer, with the choke point's checks") {
  auto& ctx = test::context();
  const uint32_t n = 3 * S4D_IOTA_WG;
  Buffer out = engine::buffer_from(ctx, "iota indirect", std::vector<uint32_t>(n, 7));
  // Two groups of three: the third group's elements keep their 7. Offset 4: any 4-byte multiple.
  Buffer args = engine::buffer_from(ctx, "indirect args", std::vector<uint32_t>{0, 2, 1, 1});
  const gpu::IotaParams params{.n = n, .first = 100, ._pad0 = 0, ._pad1 = 0};
  const uint64_t submissions = ctx.submissions(), waits = ctx.host_waits();
  Recorder rec(ctx, "iota indirect");
  rec.dispatch_indirect(iota_pipeline(), {S4D_BIND(IOTA_OUT, out)}, params, args, 4);
  ctx.run(std::move(rec));
  CHECK(ctx.submissions() - submissions == 1);
  CHECK(ctx.host_waits() - waits == 1);
  const auto got = ctx.download<uint32_t>(out, n);
  size_t bad = 0;
  for (uint32_t i = 0; i < n; ++i) bad += got[i] != (i < 2 * S4D_IOTA_WG ? 100 + i : 7u);
  CHECK(bad == 0);
  Recorder bad_rec(ctx, "bad indirect");
  CHECK_THROWS_WITH_AS(bad_rec.dispatch_indirect(iota_pipeline(), {S4D_BIND(IOTA_OUT, out)}, params, args, 6),
                       doctest::Contains("4-byte aligned"), std::invalid_argument);
  CHECK_THROWS_WITH_AS(bad_rec.dispatch_indirect(iota_pipeline(), {S4D_BIND(IOTA_OUT, out)}, params, args, 8),
                       doctest::Contains("inside buffer 'indirect args'"), std::invalid_argument);
  const uint32_t too_small = 3;
  CHECK_THROWS_WITH_AS(bad_rec.dispatch_indirect(iota_pipeline(), {S4D_BIND(IOTA_OUT, out)}, too_small, args, 0),
                       doctest::Contains("push constants are 4 bytes"), std::invalid_argument);
}

TEST_CASE("buffers bind by their ids in any order") {
  auto& ctx = test::context();
  const uint32_t n = 300;
  std::vector<float> dst(n), src(n);
  for (uint32_t i = 0; i < n; ++i) {
    dst[i] = static_cast<float>(i);
    src[i] = static_cast<float>(2 * i);
  }
  Buffer bdst(ctx, "dst", n * 4), bsrc(ctx, "src", n * 4);
  ctx.upload(bdst, dst.data(), n * 4);
  ctx.upload(bsrc, src.data(), n * 4);
  Recorder rec(ctx, "grad_add by id");
  rec.dispatch(add_pipeline(), {S4D_BIND(ADD_SRC, bsrc), S4D_BIND(ADD_DST, bdst)},
               gpu::AddParams{.n = n, ._pad0 = 0, ._pad1 = 0, ._pad2 = 0}, (n + S4D_ADD_WG - 1) / S4D_ADD_WG);
  ctx.run(std::move(rec));
  const auto got_dst = ctx.download<float>(bdst, n);
  const auto got_src = ctx.download<float>(bsrc, n);
  size_t bad = 0;
  for (uint32_t i = 0; i < n; ++i) bad += got_dst[i] != static_cast<float>(3 * i) || got_src[i] != src[i];
  CHECK(bad == 0);  // small integers: exact in float
}

TEST_CASE("a buffer bound to a missing, repeated or foreign binding id is refused, naming the binding") {
  auto& ctx = test::context();
  Buffer dst(ctx, "dst", 64), src(ctx, "src", 64);
  Recorder rec(ctx, "bad bindings");
  const gpu::AddParams params{.n = 16, ._pad0 = 0, ._pad1 = 0, ._pad2 = 0};
  CHECK_THROWS_WITH_AS(rec.dispatch(add_pipeline(), {S4D_BIND(ADD_DST, dst)}, params, 1),
                       doctest::Contains("dispatch of 'grad_add': binding 1 (block 'Src') is not bound"),
                       std::invalid_argument);
  CHECK_THROWS_WITH_AS(rec.dispatch(add_pipeline(), {S4D_BIND(ADD_DST, dst), S4D_BIND(ADD_DST, src)}, params, 1),
                       doctest::Contains("binding 0 is bound twice, as S4D_B_ADD_DST and as S4D_B_ADD_DST"),
                       std::invalid_argument);
  CHECK_THROWS_WITH_AS(
      rec.dispatch(add_pipeline(), {S4D_BIND(ADD_DST, dst), S4D_BIND(ADD_SRC, src), S4D_BIND(ADAM_GRADS, src)}, params, 1),
      doctest::Contains("S4D_B_ADAM_GRADS is binding 2, but the shader declares bindings 0..1"), std::invalid_argument);
  // grad_mask's S4D_B_MASK_VALUES is binding 0 too: only the names tell the kernels apart.
  CHECK_THROWS_WITH_AS(rec.dispatch(add_pipeline(), {S4D_BIND(MASK_VALUES, dst), S4D_BIND(ADD_SRC, src)}, params, 1),
                       doctest::Contains("S4D_B_MASK_VALUES is binding 0, where the shader declares block 'Dst'"),
                       std::invalid_argument);
  CHECK_THROWS_WITH_AS(rec.dispatch(add_pipeline(), {S4D_BIND(ADD_DST, dst), S4D_BIND(MASK_ROWS, src)}, params, 1),
                       doctest::Contains("S4D_B_MASK_ROWS is binding 1, where the shader declares block 'Src'"),
                       std::invalid_argument);
}

TEST_CASE("a buffer larger than the device allows is refused naming the buffer and the limit") {
  auto& ctx = test::context();
  const uint64_t limit = ctx.info().max_storage_buffer_range;
  CHECK_THROWS_WITH_AS(Buffer(ctx, "gaussian means", static_cast<size_t>(limit) + 4),
                       doctest::Contains("buffer 'gaussian means'"), std::invalid_argument);
  CHECK_THROWS_WITH_AS(Buffer(ctx, "gaussian means", static_cast<size_t>(limit) + 4),
                       doctest::Contains("maxStorageBufferRange"), std::invalid_argument);
}

TEST_CASE("timestamps bracket a dispatch") {
  auto& ctx = test::context();
  if (!ctx.info().timestamps) return;
  Buffer out(ctx, "timed iota", 1 << 20);
  engine::TimestampQueries q(ctx, 2, "timed iota queries");
  Recorder rec(ctx, "timed iota");
  rec.reset_queries(q);
  rec.timestamp(q, 0);
  primitives::cmd_iota(rec, out, (1 << 20) / 4);
  rec.timestamp(q, 1);
  ctx.run(std::move(rec));
  const double ms = q.elapsed_ms(0, 1);
  CHECK(ms >= 0.0);
  CHECK(ms < 60'000.0);
}

TEST_CASE("buffers dropped while their work is in flight are freed after it completes") {
  auto& ctx = test::context();
  uint64_t ticket;
  {
    Buffer scratch(ctx, "short-lived", 1 << 16);
    Recorder rec(ctx, "uses short-lived");
    primitives::cmd_iota(rec, scratch, (1 << 16) / 4);
    ticket = ctx.submit(std::move(rec));
  }  // destroyed here, while the GPU may still be writing it: retired, not freed
  ctx.wait(ticket);
  Buffer again(ctx, "after", 64);
  CHECK(again.valid());
}

TEST_CASE("without mapped device memory, uploads, readbacks and kernels go through staging buffers") {
  engine::ContextOptions options = engine::ContextOptions::from_env();
  options.validation = test::context().validation_enabled();
  options.map_device_memory = false;
  engine::Context ctx(options);
  CHECK(!ctx.unified_memory());
  Buffer b(ctx, "staged", 5000 * 4);
  CHECK(b.mapped() == nullptr);
  std::vector<uint32_t> data(5000);
  std::iota(data.begin(), data.end(), 100u);
  ctx.upload(b, std::span<const uint32_t>(data), 0);
  test::expect_equal_arrays(ctx.download<uint32_t>(b, 5000), data, "staged round trip");
  Recorder rec(ctx, "iota staged");
  primitives::cmd_iota(rec, b, 5000, 1);
  ctx.run(std::move(rec));
  const auto got = ctx.download<uint32_t>(b, 3, 4997);
  CHECK(got == std::vector<uint32_t>{4998, 4999, 5000});
  CHECK(ctx.take_validation_messages().empty());
}

TEST_CASE("a buffer dropped while a recorder that uses it is still open lives until that submission completes") {
  auto& ctx = test::context();
  Recorder rec(ctx, "records before the buffer is dropped");
  {
    Buffer transient(ctx, "dropped before submit", 1 << 12);
    primitives::cmd_iota(rec, transient, (1 << 12) / 4);
  }  // must be retired, not destroyed: the command buffer still references it
  ctx.run(std::move(rec));
  CHECK(ctx.take_validation_messages().empty());  // the layer reports use of a destroyed buffer
}

TEST_CASE("a buffer dropped while its recorder is open outlives another submission that completes first") {
  // An upload through staging (a GPU's device-local memory) or another recorder may be submitted
  // and waited for while the first recorder is still open; the buffer must survive it (found on an
  // NVIDIA H200, where an nn test's temporary input was freed by an upload's wait and read as garbage).
  auto& ctx = test::context();
  Recorder rec(ctx, "records before the buffer is dropped");
  {
    Buffer transient(ctx, "dropped before another submission", 1 << 12);
    primitives::cmd_iota(rec, transient, (1 << 12) / 4);
  }  // retired while `rec` is open
  Buffer other(ctx, "written by another submission", 64);
  Recorder first(ctx, "submitted and completed first");
  primitives::cmd_iota(first, other, 16);
  ctx.run(std::move(first));  // completes before `rec` is submitted: `transient` must still live
  ctx.run(std::move(rec));
  CHECK(ctx.take_validation_messages().empty());  // the layer reports use of a destroyed buffer
}

TEST_CASE("what is retired while a recorder is open is freed by wait_idle when that recorder is dropped unsubmitted") {
  auto& ctx = test::context();
  bool freed = false;
  {
    Recorder rec(ctx, "dropped without a submission");
    ctx.retire([&freed] { freed = true; });  // waits for the open recorder's submission
    CHECK(!freed);
  }
  ctx.wait_idle();
  CHECK(freed);  // before: kept until the context's end, and never run there either
}

TEST_CASE("staging buffers cannot be bound to a shader") {
  auto& ctx = test::context();
  Buffer staging(ctx, "host staging", 64, engine::BufferKind::staging);
  Recorder rec(ctx, "bind staging");
  CHECK_THROWS_WITH_AS(rec.dispatch(iota_pipeline(), {S4D_BIND(IOTA_OUT, staging)}, gpu::IotaParams{}, 1),
                       doctest::Contains("S4D_B_IOTA_OUT: buffer 'host staging' is a staging buffer"),
                       std::invalid_argument);
}

TEST_CASE("presentation options: a missing extension or no presenting queue is refused, saying why") {
  engine::ContextOptions missing_instance = engine::ContextOptions::from_env();
  missing_instance.instance_extensions = {"VK_S4D_no_such_instance_extension"};
  CHECK_THROWS_WITH(engine::Context{missing_instance},
                    doctest::Contains("lacks the extension VK_S4D_no_such_instance_extension"));

  engine::ContextOptions missing_device = engine::ContextOptions::from_env();
  missing_device.device_extensions = {"VK_S4D_no_such_device_extension"};
  CHECK_THROWS_WITH(engine::Context{missing_device}, doctest::Contains("lacks VK_S4D_no_such_device_extension"));

  engine::ContextOptions cannot_present = engine::ContextOptions::from_env();
  cannot_present.can_present = [](VkInstance, VkPhysicalDevice, uint32_t) { return false; };
  CHECK_THROWS_WITH(engine::Context{cannot_present}, doctest::Contains("cannot present to the window"));

  // Where a family can present, the context comes up on it.
  engine::ContextOptions presents = engine::ContextOptions::from_env();
  std::vector<uint32_t> accepted;
  presents.can_present = [&](VkInstance, VkPhysicalDevice, uint32_t family) {
    accepted.push_back(family);
    return true;
  };
  engine::Context ctx(presents);
  CHECK(std::find(accepted.begin(), accepted.end(), ctx.queue_family()) != accepted.end());
}

TEST_CASE("device memory in use and its peak follow buffers, moves and resets") {
  engine::Context& ctx = test::context();
  const uint64_t before = ctx.memory_in_use();
  ctx.reset_memory_peak();
  {
    Buffer a(ctx, "counted a", 1 << 20);
    CHECK(ctx.memory_in_use() >= before + (1 << 20));  // allocations round up, never down
    const uint64_t with_a = ctx.memory_in_use();
    Buffer b(ctx, "counted b", 3 << 20);
    const uint64_t with_both = ctx.memory_in_use();
    CHECK(with_both >= with_a + (3 << 20));
    Buffer moved = std::move(b);  // a move hands the count over, it does not double it
    CHECK(ctx.memory_in_use() == with_both);
    moved = Buffer();
    CHECK(ctx.memory_in_use() == with_a);
    CHECK(ctx.memory_peak() == with_both);
    ctx.reset_memory_peak();
    CHECK(ctx.memory_peak() == with_a);
  }
  CHECK(ctx.memory_in_use() == before);
}
