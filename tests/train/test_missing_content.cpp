// Growth into missed content, the prune floor and the moving-content PSNR, on the host: missed
// pixels are the worst per cell above the threshold; the plane sweep finds a textured patch's depth
// from other views; seeds land on the patch; the floor keeps the most opaque; the moving PSNR pools
// exactly the pixels that differ from the temporal median.
#include <doctest/doctest.h>

#include <cmath>
#include <numeric>

#include "s4d/io/moving_content.h"
#include "s4d/train/missing_content.h"
#include "s4d/train/prune_floor.h"

using namespace s4d;

namespace {

// A camera at `centre` looking along +z (OpenCV axes, identity rotation).
io::CameraView camera_at(double x, double y, double z, int size, double focal) {
  io::CameraView c;
  c.world_to_cam = {1, 0, 0, -x, 0, 1, 0, -y, 0, 0, 1, -z, 0, 0, 0, 1};
  c.fx = c.fy = focal, c.cx = c.cy = size / 2.0, c.width = c.height = size;
  return c;
}

// A textured square in the plane z = depth over |x|, |y| <= half on a black sky, seen by `cam`
// (ray-cast per pixel centre).
io::ImageF view_of_square(const io::CameraView& cam, double depth, double half) {
  io::ImageF im{cam.width, cam.height, 3, std::vector<float>(size_t(cam.width) * cam.height * 3, 0.0f)};
  const double ox = -cam.world_to_cam[3], oy = -cam.world_to_cam[7], oz = -cam.world_to_cam[11];
  for (int y = 0; y < cam.height; ++y)
    for (int x = 0; x < cam.width; ++x) {
      const double dx = (x + 0.5 - cam.cx) / cam.fx, dy = (y + 0.5 - cam.cy) / cam.fy;
      const double s = depth - oz, wx = ox + dx * s, wy = oy + dy * s;
      if (std::abs(wx) > half || std::abs(wy) > half) continue;
      // A two-colour texture a few pixels in period, so colours identify places on the square.
      const size_t i = (size_t(y) * cam.width + x) * 3;
      im.data[i] = float(0.5 + 0.4 * std::sin(20 * wx)), im.data[i + 1] = float(0.5 + 0.4 * std::cos(17 * wy)), im.data[i + 2] = 0.8f;
    }
  return im;
}

}  // namespace

TEST_CASE("missed pixels: the worst of each cell above the threshold, worst first, capped") {
  io::ImageF truth{8, 4, 3, std::vector<float>(8 * 4 * 3, 0.0f)}, render = truth;
  auto set = [&](int x, int y, float v) { for (int c = 0; c < 3; ++c) truth.data[(size_t(y) * 8 + x) * 3 + c] = v; };
  set(1, 1, 0.9f), set(2, 2, 0.5f);  // one cell: the 0.9 wins
  set(5, 0, 0.3f);                    // the next cell: mean error 0.3 > 0.25
  set(6, 3, 0.2f);                    // below the threshold
  train::SeedSettings s;
  const auto missed = train::missed_pixels(render, truth, s);
  REQUIRE(missed.size() == 2);
  CHECK(missed[0].x == 1);
  CHECK(missed[0].y == 1);
  CHECK(missed[0].error == doctest::Approx(0.9f));
  CHECK(missed[1].x == 5);
  s.max_seeds = 1;
  CHECK(train::missed_pixels(render, truth, s).size() == 1);
}

TEST_CASE("the plane sweep finds a textured square's depth from two other views, and seeds land on it") {
  const int size = 64;
  const double focal = 60, depth = 4.0;
  const io::CameraView src = camera_at(0, 0, 0, size, focal), left = camera_at(-0.6, 0, 0, size, focal),
                       up = camera_at(0.3, -0.5, 0, size, focal);
  const io::ImageF a = view_of_square(src, depth, 1.0), b = view_of_square(left, depth, 1.0), c = view_of_square(up, depth, 1.0);
  const std::vector<train::ViewImage> others{{&b, left}, {&c, up}};
  const std::array<float, 3> lo{-3, -3, 1}, hi{3, 3, 9};
  train::SeedSettings s;
  s.depth_samples = 128;  // 8 / 128 = 0.0625 between samples along z
  for (const std::pair<double, double>& xy : {std::pair{32.5, 32.5}, {20.5, 40.5}, {45.5, 25.5}}) {
    const double x = xy.first, y = xy.second;  // not a structured binding: doctest's macros capture it
    CAPTURE(x);
    CAPTURE(y);
    const auto d = train::consistent_depth({&a, src}, x, y, others, lo, hi, s);
    REQUIRE(d);
    // Worst case measured 0.03: one sample spacing, as the texture varies slowly.
    CHECK(std::abs(*d - depth) <= 0.0625);
  }
  // A pixel of sky (black) over a black sky agrees everywhere: any depth; a sky pixel that no
  // other view sees at all has none.
  const std::vector<train::ViewImage> none;
  CHECK_FALSE(train::consistent_depth({&a, src}, 32.5, 32.5, none, lo, hi, s));

  // The model renders nothing: every missed cell on the square gets a seed on the plane.
  const io::ImageF empty{size, size, 3, std::vector<float>(size_t(size) * size * 3, 0.0f)};
  const std::vector<float> alpha(size_t(size) * size, 0.0f), zdepth(size_t(size) * size, 0.0f);
  const auto seeds = train::find_missing_content({&a, src}, {&empty, &alpha, &zdepth}, others, lo, hi, s);
  REQUIRE(seeds.size() > 20);
  size_t on_plane = 0;
  for (const train::Seed& seed : seeds) {
    on_plane += std::abs(seed.position[2] - depth) <= 0.0625;
    CHECK(seed.scale == doctest::Approx(0.5 * 4 * seed.position[2] / focal).epsilon(1e-4));
    CHECK_FALSE(seed.from_render_depth);
  }
  // Cells on the square's border mix sky into the colour and may find no agreement or a wrong
  // depth; the interior's must be right.
  CHECK(on_plane >= seeds.size() * 8 / 10);
  // Where the model covers the pixel (alpha >= 0.5), its colour is wrong, not its geometry: no seed.
  const std::vector<float> covered(size_t(size) * size, 1.0f), covered_depth(size_t(size) * size, 2.5f);
  CHECK(train::find_missing_content({&a, src}, {&empty, &covered, &covered_depth}, others, lo, hi, s).empty());
  // Under a faint cover (alpha 0.3 here) with no view to sweep against, the render's depth
  // (sum of depth x weight / alpha) places the seed.
  const std::vector<float> faint(size_t(size) * size, 0.3f), faint_depth(size_t(size) * size, 0.75f);
  const auto at_render = train::find_missing_content({&a, src}, {&empty, &faint, &faint_depth}, {}, lo, hi, s);
  REQUIRE(!at_render.empty());
  for (const train::Seed& seed : at_render) {
    CHECK(seed.from_render_depth);
    CHECK(seed.position[2] == doctest::Approx(2.5));
  }
}

TEST_CASE("the prune floor keeps the most opaque, and only when the rule would go below it") {
  std::vector<float> o{0.001f, 0.9f, 0.002f, 0.004f, 0.5f, 0.003f};
  CHECK(train::floor_opacity(o, 0.005f, 2) == 0.005f);       // two at or above already
  CHECK(train::floor_opacity(o, 0.005f, 4) == 0.003f);       // 0.9, 0.5, 0.004, 0.003 survive "< 0.003"
  CHECK(train::floor_opacity(o, 0.005f, 100) == 0.001f);     // no more than all
  CHECK(train::floor_opacity({}, 0.005f, 4) == 0.005f);
}

TEST_CASE("moving-content PSNR pools the squared error over the pixels that differ from the temporal median") {
  // Three 4x1 frames: pixel 0 static grey, pixel k (1..3) lit in frame k-1 only.
  std::vector<io::ImageF> truth(3, io::ImageF{4, 1, 3, std::vector<float>(12, 0.0f)});
  for (size_t f = 0; f < 3; ++f) {
    for (int c = 0; c < 3; ++c) truth[f].data[size_t(c)] = 0.5f, truth[f].data[(f + 1) * 3 + size_t(c)] = 1.0f;
  }
  std::vector<io::ImageF> render = truth;
  render[0].data[3] = 0.8f;  // frame 0's moving pixel, red off by 0.2
  render[2].data[0] = 0.0f;  // a static pixel wrong: not counted
  std::vector<const io::ImageF*> r, t;
  for (size_t f = 0; f < 3; ++f) r.push_back(&render[f]), t.push_back(&truth[f]);
  io::MovingPsnr m;
  m.add(r, t);
  const io::MovingScore s = m.score();
  REQUIRE(s.psnr);
  // One moving pixel per frame: 9 values, one of them off by 0.2.
  CHECK(*s.psnr == doctest::Approx(-10 * std::log10(0.04 / 9)));
  CHECK(s.moving_share == doctest::Approx(3.0 / 12));
  io::MovingPsnr two;
  two.add({r[0], r[1]}, {t[0], t[1]});
  CHECK_FALSE(two.score().psnr);
  CHECK(two.score().why.find("3 or more times") != std::string::npos);
}
