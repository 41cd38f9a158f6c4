// DyNeRF / Neu3D with one camNN.mp4 per camera: the views match those of frame folders, the frame
// cache decodes frames close to what was written (mp4v is lossy), and the decoding order does not
// change a frame.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>

#include "data_test_util.h"
#include "s4d/data/frame_cache.h"

using namespace s4d;

TEST_CASE("dynerf videos give one view per frame with the frame-folder names and times") {
  test::TempDir dir("video_views");
  const auto root = dir / "scene";
  test::write_dynerf_videos(root, test::dynerf_cameras(), {5, 5, 5});
  const data::Dataset d = data::load_dataset(root);
  CHECK(d.kind == "dynerf");
  REQUIRE(d.views.size() == 15);
  for (size_t i = 0; i < d.views.size(); ++i) {
    const data::View& v = d.views[i];
    const size_t c = i / 5, f = i % 5;
    CHECK(v.name == "cam0" + std::to_string(c) + "/000" + std::to_string(f));
    CHECK(v.image == root / ("cam0" + std::to_string(c) + ".mp4"));
    CHECK(v.frame_in_file == static_cast<int>(f));
    CHECK(v.camera_index == static_cast<int>(c));
    CHECK(v.test == (c == 0));
    CHECK(v.time == doctest::Approx(static_cast<double>(f) / 4.0));
    CHECK(v.camera.width == 16);
    CHECK(v.camera.height == 12);
    CHECK(v.camera.fx == 10);
  }
}

TEST_CASE("frame cache decodes video frames close to the frames written") {
  test::TempDir dir("video_frames");
  const auto root = dir / "scene";
  test::write_dynerf_videos(root, test::dynerf_cameras());
  const data::Dataset d = data::load_dynerf(root);
  data::FrameCache cache(d, 1 << 20);
  double worst = 0, sum = 0;
  size_t count = 0;
  for (const data::View& v : d.views) {
    const io::ImageF& im = cache.get(v);
    REQUIRE(im.width == 16);
    REQUIRE(im.height == 12);
    REQUIRE(im.channels == 3);
    const io::ImageF written = test::smooth_pattern(16, 12, v.camera_index * 10 + v.frame_in_file);
    for (size_t k = 0; k < im.data.size(); ++k) {
      REQUIRE(std::isfinite(im.data[k]));
      const double e = std::abs(static_cast<double>(im.data[k]) - written.data[k]);
      worst = std::max(worst, e);
      sum += e;
      ++count;
    }
  }
  // mp4v at OpenCV's fixed ~1 bit per pixel, 4:2:0 chroma, 8-bit. Measured (OpenCV 4.6.0, FFmpeg 5.1,
  // Debian 12): worst 20.9 / 255, mean 2.75 / 255; bounds are those plus about 5 %.
  CHECK(worst <= 22.0 / 255);
  CHECK(sum / static_cast<double>(count) <= 2.9 / 255);
}

TEST_CASE("video frames decoded out of order equal the frames decoded in order") {
  test::TempDir dir("video_order");
  const auto root = dir / "scene";
  test::write_dynerf_videos(root, test::dynerf_cameras(), {20, 20, 20});
  const data::Dataset d = data::load_dynerf(root, {.downscale = 2, .background = {}});
  std::vector<std::vector<float>> in_order;
  {
    data::FrameCache cache(d, 1);  // holds one frame: every get() decodes
    for (const data::View& v : d.views) in_order.push_back(cache.get(v).data);
  }
  // Backwards (a seek per frame), short jumps ahead (decoded through), a long one (a seek), repeats,
  // and cameras interleaved. Camera c's frame f is view 20 c + f.
  const std::vector<size_t> order = {5, 4, 3, 2, 1, 0, 19, 59, 40, 58, 0, 5, 21, 23, 22, 25, 20, 20, 46};
  data::FrameCache cache(d, 1);
  for (const size_t i : order) {
    CAPTURE(i);
    // Decoding is deterministic, so the frame is bit-identical whichever way the decoder got there.
    CHECK(cache.get(d.views[i]).data == in_order[i]);
  }
}

TEST_CASE("a camera with a frame folder uses it and ignores its video") {
  test::TempDir dir("video_and_folder");
  const auto root = dir / "scene";
  test::write_dynerf(root, test::dynerf_cameras());
  test::write_raw(root / "cam01.mp4", "not a video; never opened");
  const data::Dataset d = data::load_dynerf(root);
  REQUIRE(d.views.size() == 12);
  CHECK(d.views[4].image == root / "cam01" / "0000.png");
  CHECK(d.views[4].frame_in_file == -1);
}
