// The built-in synthetic scene read back by the DyNeRF loader: the two were written against the
// same LLFF convention in parallel, so this checks they agree (camera centres, viewing direction,
// times, image sizes and the point cloud). Written as videos, it loads as the same views, with frames
// that differ from the lossless ones only by mp4v's loss.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "s4d/data/dataset.h"
#include "s4d/data/frame_cache.h"
#include "s4d/synth/dataset.h"

namespace fs = std::filesystem;

TEST_CASE("a synth dataset loads as DyNeRF with every camera looking at the scene centre") {
  const fs::path dir = fs::temp_directory_path() / "s4d_synth_roundtrip";
  fs::remove_all(dir);
  s4d::synth::write_dataset(dir, {.cams = 3, .frames = 3, .width = 40, .height = 30, .seed = 1, .samples_per_axis = 1, .points = 200});
  const s4d::data::Dataset d = s4d::data::load_dynerf(dir);
  REQUIRE(d.views.size() == 9);
  CHECK(d.points.size() / 3 >= 190);  // synth spreads ~200 points over the surfaces by area (rounding)
  CHECK(d.points.size() == d.colors.size());
  for (const auto& v : d.views) {
    const auto& M = v.camera.world_to_cam;
    // The scene centre (the origin) is in front of the camera and projects near the image centre
    // (synth aims every camera at it).
    const double z = M[11], x = M[3], y = M[7];
    REQUIRE(z > 1.0);
    CHECK(std::abs(v.camera.fx * x / z + v.camera.cx - 20.0) < 1.0);
    CHECK(std::abs(v.camera.fy * y / z + v.camera.cy - 15.0) < 1.0);
    // The world's up (+y) points up in the image: camera y (down) of a point above the centre is negative.
    CHECK(M[5] < 0);
    CHECK((v.time == 0.0 || v.time == 0.5 || v.time == 1.0));
  }
  CHECK(d.views[0].test);  // cam00 held out
  s4d::data::FrameCache cache(d, 1 << 20);
  const auto& img = cache.get(d.views[4]);
  CHECK(img.width == 40);
  CHECK(img.height == 30);
  CHECK(img.channels == 3);
}

TEST_CASE("a synth dataset written as videos loads as the same views, frames within mp4v's loss") {
  const fs::path dir = fs::temp_directory_path() / "s4d_synth_roundtrip_video";
  fs::remove_all(dir);
  s4d::synth::SynthOptions options{.cams = 2, .frames = 3, .width = 40, .height = 30, .seed = 1, .samples_per_axis = 1,
                                   .points = 50};
  s4d::synth::write_dataset(dir / "png", options);
  options.video = true;
  s4d::synth::write_dataset(dir / "mp4", options);
  CHECK(fs::exists(dir / "mp4" / "cam01.mp4"));
  CHECK_FALSE(fs::exists(dir / "mp4" / "cam01"));
  const s4d::data::Dataset png = s4d::data::load_dynerf(dir / "png"), mp4 = s4d::data::load_dynerf(dir / "mp4");
  REQUIRE(mp4.views.size() == png.views.size());
  s4d::data::FrameCache png_frames(png, 1 << 20), mp4_frames(mp4, 1 << 20);
  double worst = 0, sum = 0;
  size_t count = 0;
  for (size_t i = 0; i < png.views.size(); ++i) {
    CHECK(mp4.views[i].name == png.views[i].name);
    CHECK(mp4.views[i].time == png.views[i].time);
    CHECK(mp4.views[i].camera.world_to_cam == png.views[i].camera.world_to_cam);  // same poses, same code: exact
    const auto& a = png_frames.get(png.views[i]).data;
    const auto& b = mp4_frames.get(mp4.views[i]).data;
    REQUIRE(a.size() == b.size());
    for (size_t k = 0; k < a.size(); ++k) {
      const double e = std::abs(static_cast<double>(a[k]) - b[k]);
      worst = std::max(worst, e);
      sum += e;
      ++count;
    }
  }
  // The scene's checkers, stripes and noise at 40x30 are the hard case for mp4v (fixed ~1 bit per
  // pixel, 4:2:0 chroma): sharp coloured edges ring. Measured (OpenCV 4.6.0, FFmpeg 5.1, Debian 12):
  // worst 125 / 255 at such an edge, mean 10.7 / 255; bounds are those plus about 5 %. The mean is the
  // meaningful check: a wrong frame, camera or channel order gives a mean of tens of levels.
  CHECK(worst <= 132.0 / 255);
  CHECK(sum / static_cast<double>(count) <= 11.2 / 255);
  fs::remove_all(dir);
}

TEST_CASE("synth refuses --video with an odd size") {
  CHECK_THROWS_WITH_AS(s4d::synth::check_options({.cams = 2, .frames = 2, .width = 41, .height = 30, .video = true}),
                       doctest::Contains("--size must be even on both sides with --video"), std::invalid_argument);
}
