// The built-in synthetic scene read back by the DyNeRF loader: the two were written against the
// same LLFF convention in parallel, so this checks they agree (camera centres, viewing direction,
// times, image sizes and the point cloud).
#include <doctest/doctest.h>

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
