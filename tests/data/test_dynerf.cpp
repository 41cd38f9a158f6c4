// DyNeRF / Neu3D loading: LLFF pose conversion against hand-computed pixels, split, times, extent,
// downscaling, the optional point cloud.
#include <doctest/doctest.h>

#include "data_test_util.h"
#include "s4d/data/frame_cache.h"

using namespace s4d;

TEST_CASE("dynerf: poses, intrinsics, times, split and extent") {
  test::TempDir dir("dynerf_basic");
  const auto root = dir / "scene";
  const auto cams = test::dynerf_cameras();
  test::write_dynerf(root, cams);
  const data::Dataset d = data::load_dataset(root);

  CHECK(d.kind == "dynerf");
  REQUIRE(d.views.size() == 12);
  CHECK(d.points.empty());
  CHECK(d.background == std::array<float, 3>{0, 0, 0});
  for (size_t i = 0; i < d.views.size(); ++i) {
    const data::View& v = d.views[i];
    const size_t c = i / 4, f = i % 4;
    CHECK(v.name == "cam0" + std::to_string(c) + "/000" + std::to_string(f));
    CHECK(v.camera_index == static_cast<int>(c));
    CHECK(v.test == (c == 0));
    CHECK(v.time == doctest::Approx(static_cast<double>(f) / 3.0));
    CHECK(v.image == root / ("cam0" + std::to_string(c)) / ("000" + std::to_string(f) + ".png"));
    CHECK(v.camera.width == 16);
    CHECK(v.camera.height == 12);
    CHECK(v.camera.fx == 10);
    CHECK(v.camera.fy == 10);
    CHECK(v.camera.cx == 8);
    CHECK(v.camera.cy == 6);
    const Vec3 o = test::centre(v.camera);
    for (size_t k = 0; k < 3; ++k) CHECK(o[k] == doctest::Approx(cams[c].centre[k]));
    // Every camera looks at the origin: it lands on the principal point, in front of the camera.
    const Vec3 p = test::project(v.camera, {0, 0, 0});
    CHECK(p[0] == doctest::Approx(8));
    CHECK(p[1] == doctest::Approx(6));
    CHECK(p[2] > 0);
  }

  // cam00: world +x is image right, world +y is image up (v decreases), depth 5, focal 10.
  const io::CameraView& c0 = d.views[0].camera;
  const Vec3 px = test::project(c0, {1, 0, 0}), py = test::project(c0, {0, 1, 0});
  CHECK(px[0] == doctest::Approx(10));
  CHECK(px[1] == doctest::Approx(6));
  CHECK(py[0] == doctest::Approx(8));
  CHECK(py[1] == doctest::Approx(4));
  CHECK(py[2] == doctest::Approx(5));

  // Extent from the train cameras only (cam01, cam02): 1.1 x half their distance.
  const Vec3 a = cams[1].centre, b = cams[2].centre;
  const double half = 0.5 * std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
  CHECK(d.extent == doctest::Approx(1.1 * half));
}

TEST_CASE("dynerf: one frame per camera has time 0") {
  test::TempDir dir("dynerf_single");
  test::write_dynerf(dir / "s", test::dynerf_cameras(), 1);
  const data::Dataset d = data::load_dynerf(dir / "s");
  REQUIRE(d.views.size() == 3);
  for (const auto& v : d.views) CHECK(v.time == 0);
}

TEST_CASE("dynerf: downscale 2 halves intrinsics and box-filters frames") {
  test::TempDir dir("dynerf_downscale");
  const auto root = dir / "scene";
  test::write_dynerf(root, test::dynerf_cameras());
  const data::Dataset d = data::load_dynerf(root, {.downscale = 2, .background = {}});
  CHECK(d.downscale == 2);
  const data::View& v = d.views[5];  // cam01, frame 1
  CHECK(v.camera.width == 8);
  CHECK(v.camera.height == 6);
  CHECK(v.camera.fx == 5);
  CHECK(v.camera.fy == 5);
  CHECK(v.camera.cx == 4);
  CHECK(v.camera.cy == 3);
  CHECK(test::project(d.views[0].camera, {1, 0, 0})[0] == doctest::Approx(5));

  data::FrameCache cache(d, 1 << 20);
  const io::ImageF& im = cache.get(v);
  REQUIRE(im.width == 8);
  REQUIRE(im.height == 6);
  REQUIRE(im.channels == 3);
  for (int y = 0; y < 6; ++y) {
    for (int x = 0; x < 8; ++x) {
      for (int k = 0; k < 3; ++k) {
        float sum = 0;
        for (int dy = 0; dy < 2; ++dy) {
          for (int dx = 0; dx < 2; ++dx) sum += test::level(2 * x + dx, 2 * y + dy, k, 11);
        }
        CHECK(im.data[static_cast<size_t>((y * 8 + x) * 3 + k)] == doctest::Approx(sum / 4).epsilon(1e-6));
      }
    }
  }
}

TEST_CASE("dynerf: points3D.ply gives the initial point cloud") {
  test::TempDir dir("dynerf_points");
  const auto root = dir / "scene";
  test::write_dynerf(root, test::dynerf_cameras(), 1);
  std::string ply =
      "ply\nformat binary_little_endian 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
      "property float z\nproperty float nx\nproperty uchar red\nproperty uchar green\nproperty uchar blue\n"
      "end_header\n";
  for (int i = 0; i < 2; ++i) {
    for (float v : {1.5f * static_cast<float>(i), -2.0f, 0.25f, 9.0f}) test::append_le(ply, v);
    for (unsigned char c : {static_cast<unsigned char>(255 * i), static_cast<unsigned char>(51), static_cast<unsigned char>(0)}) ply += static_cast<char>(c);
  }
  test::write_raw(root / "points3D.ply", ply);
  const data::Dataset d = data::load_dynerf(root);
  CHECK(d.points == std::vector<float>{0, -2, 0.25f, 1.5f, -2, 0.25f});
  CHECK(d.colors == std::vector<float>{0, 0.2f, 0, 1, 0.2f, 0});

  test::write_raw(root / "points3D.ply",
                  "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n"
                  "property uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n1 2 3 255 0 51\n");
  const data::Dataset e = data::load_dynerf(root);
  CHECK(e.points == std::vector<float>{1, 2, 3});
  CHECK(e.colors == std::vector<float>{1, 0, 0.2f});
}
