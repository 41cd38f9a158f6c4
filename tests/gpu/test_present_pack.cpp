// present_pack on the device against its CPU twin (viewer/include/s4d/viewer/present_pack_ref.h):
// at equal sizes pixel for pixel (the unscaled viewer frame and captures), and upsampled from the
// smaller images the viewer renders while the view moves.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <random>
#include <vector>

#include "s4d/engine/buffer.h"
#include "s4d/engine/recorder.h"
#include "s4d/scene/static_scene.h"
#include "s4d/viewer/frame_renderer.h"
#include "s4d/viewer/present_pack_ref.h"
#include "test_context.h"

using namespace s4d;

namespace {

// Values past both ends of [0, 1] (clamped), exact levels and a NaN (level 0).
std::vector<float> test_image(uint32_t width, uint32_t height, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-0.2f, 1.2f);
  std::vector<float> rgb(size_t{width} * height * 3);
  for (float& v : rgb) v = u(rng);
  rgb[0] = std::numeric_limits<float>::quiet_NaN();
  rgb[rgb.size() - 1] = 128.0f / 255.0f;
  return rgb;
}

std::vector<uint32_t> pack_on_device(const std::vector<float>& rgb, uint32_t src_width, uint32_t src_height,
                                     uint32_t width, uint32_t height, viewer::PixelOrder order) {
  engine::Context& ctx = test::context();
  engine::Buffer src(ctx, "pack test rgb", rgb.size() * 4);
  engine::Buffer out(ctx, "pack test pixels", size_t{width} * height * 4);
  ctx.upload(src, std::span<const float>(rgb));
  engine::Recorder rec(ctx, "pack test");
  viewer::record_present_pack(ctx, rec, src, src_width, src_height, out, width, height, order);
  ctx.run(std::move(rec));
  return ctx.download<uint32_t>(out, size_t{width} * height);
}

// The largest difference of one channel's level between two packed images.
uint32_t max_level_difference(const std::vector<uint32_t>& a, const std::vector<uint32_t>& b) {
  uint32_t worst = 0;
  for (size_t i = 0; i < a.size(); ++i)
    for (int shift = 0; shift < 32; shift += 8) {
      const int la = static_cast<int>((a[i] >> shift) & 0xffu), lb = static_cast<int>((b[i] >> shift) & 0xffu);
      worst = std::max(worst, static_cast<uint32_t>(std::abs(la - lb)));
    }
  return worst;
}

}  // namespace

TEST_CASE("present_pack at equal sizes is the per-pixel quantisation, bit for bit") {
  const uint32_t w = 37, h = 23;
  const std::vector<float> rgb = test_image(w, h, 1);
  for (const viewer::PixelOrder order : {viewer::PixelOrder::rgba, viewer::PixelOrder::bgra}) {
    const std::vector<uint32_t> gpu = pack_on_device(rgb, w, h, w, h, order);
    CHECK(gpu == viewer::present_pack_ref(rgb, w, h, w, h, order == viewer::PixelOrder::bgra));
    for (size_t i = 0; i < gpu.size(); ++i) {
      const uint32_t r = viewer::pack_level(rgb[3 * i]), g = viewer::pack_level(rgb[3 * i + 1]),
                     b = viewer::pack_level(rgb[3 * i + 2]);
      const uint32_t expected = order == viewer::PixelOrder::bgra ? (b | (g << 8) | (r << 16) | (255u << 24))
                                                                  : (r | (g << 8) | (b << 16) | (255u << 24));
      REQUIRE(gpu[i] == expected);
    }
  }
}

TEST_CASE("present_pack upsamples the viewer's smaller frames as its twin does") {
  struct Case {
    uint32_t src_w, src_h, w, h;
  };
  // A quarter of 640x480 (the viewer's floor), an uneven 3/4, a tiny source, and one axis only.
  for (const Case c : {Case{160, 120, 640, 480}, Case{75, 56, 100, 75}, Case{2, 3, 17, 15}, Case{64, 48, 64, 96}}) {
    CAPTURE(c.src_w);
    CAPTURE(c.src_h);
    CAPTURE(c.w);
    CAPTURE(c.h);
    const std::vector<float> rgb = test_image(c.src_w, c.src_h, c.src_w + c.w);
    const std::vector<uint32_t> gpu = pack_on_device(rgb, c.src_w, c.src_h, c.w, c.h, viewer::PixelOrder::bgra);
    const std::vector<uint32_t> twin = viewer::present_pack_ref(rgb, c.src_w, c.src_h, c.w, c.h, true);
    // GLSL's float division and mix may round differently from C++'s (fused multiply-adds, a
    // division within 2.5 ulp), which moves a value sitting on a level's rounding edge by one
    // level. Measured on lavapipe: 0 in every case (the twin is exact there).
    CHECK(max_level_difference(gpu, twin) <= 1);
    // The double twin, the exact reference, differs from the float one only on a rounding edge.
    // Measured: 1 level (160x120 -> 640x480), 0 in the other cases.
    CHECK(max_level_difference(twin, viewer::present_pack_ref(std::vector<double>(rgb.begin(), rgb.end()), c.src_w,
                                                              c.src_h, c.w, c.h, true)) <= 1);
  }
}

TEST_CASE("pack taps align pixel centres: every source pixel lands where it should") {
  // 2x: output pixels 2i and 2i+1 sample source pixel i with weights of 1/4 towards each neighbour.
  const gpu::PackTap t0 = gpu::pack_tap(0, 4, 8), t1 = gpu::pack_tap(1, 4, 8), t2 = gpu::pack_tap(2, 4, 8);
  CHECK((t0.i0 == 0 && t0.num == 0));            // s = -0.25: clamped to pixel 0
  CHECK((t1.i0 == 0 && t1.num == 4));            // s = 0.25: 4 / 16 of pixel 1
  CHECK((t2.i0 == 0 && t2.num == 12));           // s = 0.75
  const gpu::PackTap last = gpu::pack_tap(7, 4, 8);  // s = 3.25: clamped to the last pixel
  CHECK((last.i0 == 3 && last.num == 0));
  for (uint32_t x = 0; x < 50; ++x) {
    const gpu::PackTap same = gpu::pack_tap(x, 50, 50);
    CHECK((same.i0 == x && same.num == 0));
  }
  CHECK_THROWS_AS(viewer::present_pack_ref(std::vector<float>(3 * 8 * 8), 8, 8, 4, 4, false), std::invalid_argument);
}

// The viewer's frame: the scene source, the rasterizer and the pack in one submission with one
// host wait, once the rasterizer's buffers fit (the first frame sizes them); the pixels are those
// of the same frame rendered again.
TEST_CASE("a viewer frame is one submission") {
  engine::Context& ctx = test::context();
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-1, 1);
  io::GaussianCloud cloud;
  for (int i = 0; i < 300; ++i) {
    for (float m : {u(rng), u(rng), 4 + u(rng)}) cloud.means.push_back(m);
    for (int k = 0; k < 3; ++k) cloud.log_scales.push_back(-2.5f + 0.5f * u(rng));
    for (float q : {1.0f, 0.1f * u(rng), 0.1f * u(rng), 0.1f * u(rng)}) cloud.quats.push_back(q);
    cloud.opacity_logits.push_back(u(rng));
    for (int ch = 0; ch < 3; ++ch) cloud.sh.push_back(u(rng));
  }
  scene::StaticScene source(ctx, cloud);
  splat::Camera cam;
  cam.world_to_cam = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
  cam.width = 120, cam.height = 90, cam.fx = cam.fy = 100, cam.cx = 60, cam.cy = 45;
  viewer::FrameRenderer renderer(ctx, {0, 0, 0});
  renderer.render_now(source, cam, 0.0, viewer::PixelOrder::bgra);
  const std::vector<uint32_t> first = ctx.download<uint32_t>(renderer.pixels(), size_t{120} * 90);
  for (const double scale : {1.0, 0.5}) {
    CAPTURE(scale);
    const uint64_t submissions = ctx.submissions(), waits = ctx.host_waits();
    const splat::RenderStats stats = renderer.render_now(source, cam, 0.0, viewer::PixelOrder::bgra, scale);
    CHECK(stats.instances > 0);
    CHECK(ctx.submissions() - submissions == 1);
    CHECK(ctx.host_waits() - waits == 1);
  }
  renderer.render_now(source, cam, 0.0, viewer::PixelOrder::bgra);
  CHECK(ctx.download<uint32_t>(renderer.pixels(), size_t{120} * 90) == first);
}
