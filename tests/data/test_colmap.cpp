// COLMAP multi-camera-rig loading: the built-in scene, loaded as DyNeRF for reference, is written
// again as a COLMAP model by the test's own writer (colmap_fixture.h) and must load as the same
// cameras, times, split and points; convention mistakes in the writer must show up as large
// differences, and every bad input must name its file and field.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "max_abs_diff.h"
#include "colmap_fixture.h"
#include "s4d/synth/dataset.h"

using namespace s4d;
using test::max_abs_diff;
namespace fs = std::filesystem;

namespace {

// The built-in scene (4 cameras x 3 frames of 32x24, with points) as DyNeRF, loaded as the reference.
data::Dataset synth_reference(const fs::path& dir, const data::LoadOptions& options = {}) {
  if (!fs::exists(dir)) {
    synth::write_dataset(dir, {.cams = 4, .frames = 3, .width = 32, .height = 24, .seed = 3, .samples_per_axis = 1, .points = 60});
  }
  return data::load_dynerf(dir, options);
}

// A COLMAP dataset at `root` for `model`, frames copied from the reference.
void write_fixture(const fs::path& root, const data::Dataset& ref, const test::ColmapModel& model, bool binary,
                   bool images_folder = false) {
  test::copy_frames(ref, root, images_folder);
  if (binary) {
    test::write_colmap_bin(root / "sparse" / "0", model);
  } else {
    test::write_colmap_txt(root / "sparse" / "0", model);
  }
}

double intrinsics_diff(const io::CameraView& a, const io::CameraView& b) {
  return std::max({std::abs(a.fx - b.fx), std::abs(a.fy - b.fy), std::abs(a.cx - b.cx), std::abs(a.cy - b.cy)});
}

// Worst world_to_cam and intrinsics differences over all views; the views must correspond.
std::pair<double, double> camera_diff(const data::Dataset& a, const data::Dataset& b) {
  REQUIRE(a.views.size() == b.views.size());
  double pose = 0, intrinsics = 0;
  for (size_t i = 0; i < a.views.size(); ++i) {
    pose = std::max(pose, max_abs_diff(a.views[i].camera.world_to_cam, b.views[i].camera.world_to_cam));
    intrinsics = std::max(intrinsics, intrinsics_diff(a.views[i].camera, b.views[i].camera));
  }
  return {pose, intrinsics};
}

void check_load_fails(const fs::path& root, const fs::path& file, const std::string& what) {
  CHECK_THROWS_WITH_AS(data::load_colmap(root), test::error_at(file, what), std::runtime_error);
}

}  // namespace

TEST_CASE("colmap: bin and txt models recover the reference cameras, times, split and points") {
  test::TempDir dir("colmap_roundtrip");
  const data::Dataset ref = synth_reference(dir / "synth");
  REQUIRE(ref.views.size() == 12);
  REQUIRE(ref.points.size() >= 3 * 50);
  const test::ColmapModel model = test::colmap_from(ref);

  for (const bool binary : {true, false}) {
    for (const bool images_folder : {false, true}) {
      CAPTURE(binary);
      CAPTURE(images_folder);
      const fs::path root = dir / (std::string(binary ? "bin" : "txt") + (images_folder ? "_images" : ""));
      write_fixture(root, ref, model, binary, images_folder);
      const data::Dataset d = data::load_colmap(root);
      CHECK(d.kind == "colmap");
      CHECK(d.layout == "colmap-multiview");
      CHECK(d.root == root);
      REQUIRE(d.views.size() == ref.views.size());
      for (size_t i = 0; i < d.views.size(); ++i) {
        const data::View &v = d.views[i], &r = ref.views[i];
        CHECK(v.name == r.name);
        CHECK(v.camera_index == r.camera_index);
        CHECK(v.test == r.test);
        CHECK(v.time == r.time);
        CHECK(v.frame_in_file == -1);
        const std::string folder = v.name.substr(0, v.name.find('/'));
        CHECK(v.image == (images_folder ? root / folder / "images" : root / folder) / r.image.filename());
        CHECK(v.camera.width == r.camera.width);
        CHECK(v.camera.height == r.camera.height);
      }
      CHECK(d.views[0].test);
      CHECK_FALSE(d.views[3].test);
      // Measured: worst pose difference 4.4e-16 for both bin and txt (17 digits), intrinsics exact:
      // the quaternion round trip costs a few ulps, nothing more; 1e-12 leaves room for other libms.
      const auto [pose, intrinsics] = camera_diff(d, ref);
      MESSAGE("colmap ", (binary ? "bin" : "txt"), ": worst world_to_cam difference ", pose, ", intrinsics ", intrinsics);
      CHECK(pose < 1e-12);
      CHECK(intrinsics < 1e-12);
      CHECK(d.extent == doctest::Approx(ref.extent).epsilon(1e-9));
      CHECK(d.points_file == root / "sparse" / "0" / (binary ? "points3D.bin" : "points3D.txt"));
      CHECK(d.points == ref.points);  // float -> double -> float is exact
      REQUIRE(d.colors.size() == ref.colors.size());
      for (size_t k = 0; k < d.colors.size(); ++k) CHECK(d.colors[k] == doctest::Approx(ref.colors[k]).epsilon(1e-6));
      CHECK(d.background == std::array<float, 3>{0, 0, 0});
    }
  }
}

TEST_CASE("colmap: binary preferred, points optional, downscale") {
  test::TempDir dir("colmap_options");
  const data::Dataset ref = synth_reference(dir / "synth");
  const test::ColmapModel model = test::colmap_from(ref);

  SUBCASE("the binary model wins over the text one") {
    const fs::path root = dir / "both";
    write_fixture(root, ref, model, true);
    test::write_colmap_txt(root / "sparse" / "0", test::colmap_from(ref, test::PoseConvention::cam_to_world));
    CHECK(camera_diff(data::load_colmap(root), ref).first < 1e-12);
  }

  SUBCASE("no points3D file: no initial points") {
    const fs::path root = dir / "nopoints";
    write_fixture(root, ref, model, true);
    fs::remove(root / "sparse" / "0" / "points3D.bin");
    const data::Dataset d = data::load_colmap(root);
    CHECK(d.points.empty());
    CHECK(d.points_file.empty());
    CHECK(data::load_dataset(root).layout == "colmap-multiview");  // sparse/0/ is how it is detected
  }

  SUBCASE("downscale 2 matches the DyNeRF loader's") {
    const fs::path root = dir / "down";
    write_fixture(root, ref, model, true);
    const data::Dataset d = data::load_colmap(root, {.downscale = 2, .background = {}});
    const data::Dataset r2 = synth_reference(dir / "synth", {.downscale = 2, .background = {}});
    CHECK(d.downscale == 2);
    CHECK(d.views[5].camera.width == 16);
    CHECK(camera_diff(d, r2).second < 1e-12);
  }
}

TEST_CASE("colmap: a wrong pose convention in the writer gives clearly different cameras") {
  test::TempDir dir("colmap_conventions");
  const data::Dataset ref = synth_reference(dir / "synth");
  for (const auto convention : {test::PoseConvention::cam_to_world, test::PoseConvention::xyzw}) {
    const int convention_id = static_cast<int>(convention);
    CAPTURE(convention_id);
    const fs::path root = dir / ("c" + std::to_string(static_cast<int>(convention)));
    write_fixture(root, ref, test::colmap_from(ref, convention), true);
    const data::Dataset d = data::load_colmap(root);
    REQUIRE(d.views.size() == ref.views.size());
    // Every camera must be off, not just some: the scene is a few units across, so 0.5 is gross.
    // Measured: smallest per-view difference 0.87 (camera-to-world), 1.98 (x, y, z, w order).
    double least = 1e9;
    for (size_t i = 0; i < d.views.size(); ++i) {
      least = std::min(least, max_abs_diff(d.views[i].camera.world_to_cam, ref.views[i].camera.world_to_cam));
    }
    MESSAGE("convention ", static_cast<int>(convention), ": smallest per-view world_to_cam difference ", least);
    CHECK(least > 0.5);
  }
}

TEST_CASE("colmap: intrinsics are rescaled to the frames, distortion-free models accepted") {
  test::TempDir dir("colmap_intrinsics");
  const data::Dataset ref = synth_reference(dir / "synth");

  SUBCASE("COLMAP camera at twice the frame size") {
    const test::ColmapModel model = test::colmap_from(ref, test::PoseConvention::colmap, 2.0);
    CHECK(model.cameras[0].width == 64);
    write_fixture(dir / "x2", ref, model, false);
    const data::Dataset d = data::load_colmap(dir / "x2");
    CHECK(d.views[0].camera.width == 32);
    CHECK(camera_diff(d, ref).second < 1e-12);
  }

  SUBCASE("a size within a pixel of a uniform rescale (odd full-size height)") {
    test::ColmapModel model = test::colmap_from(ref, test::PoseConvention::colmap, 2.0);
    for (auto& c : model.cameras) c.height += 1;  // 64x49: frames 32x24 are 49 / 2 rounded down
    write_fixture(dir / "odd", ref, model, true);
    const data::Dataset d = data::load_colmap(dir / "odd");
    CHECK(d.views[0].camera.cy == doctest::Approx(ref.views[0].camera.cy * 48.0 / 49.0));
    CHECK(d.views[0].camera.fx == doctest::Approx(ref.views[0].camera.fx));
  }

  SUBCASE("SIMPLE_RADIAL and OPENCV with zero distortion are pinhole") {
    test::ColmapModel model = test::colmap_from(ref);
    REQUIRE(model.cameras.size() == 4);
    const auto& p0 = model.cameras[0].params;
    REQUIRE(p0[0] == p0[1]);  // synth has one focal length, so SIMPLE_RADIAL can hold it
    model.cameras[0] = {model.cameras[0].id, 2, "SIMPLE_RADIAL", 32, 24, {p0[0], p0[2], p0[3], 0.0}};
    const auto p1 = model.cameras[1].params;
    model.cameras[1] = {model.cameras[1].id, 4, "OPENCV", 32, 24, {p1[0], p1[1], p1[2], p1[3], 0, 0, 0, 0}};
    for (const bool binary : {true, false}) {
      const fs::path root = dir / (binary ? "zero_bin" : "zero_txt");
      write_fixture(root, ref, model, binary);
      CHECK(camera_diff(data::load_colmap(root), ref).second < 1e-12);
    }
  }

  SUBCASE("a non-uniform rescale is refused") {
    test::ColmapModel model = test::colmap_from(ref, test::PoseConvention::colmap, 2.0);
    for (auto& c : model.cameras) c.height = 40;
    write_fixture(dir / "skew", ref, model, true);
    check_load_fails(dir / "skew", dir / "skew" / "sparse" / "0" / "cameras.bin",
                     "camera 10 (PINHOLE): width, height: 64x40 is not a uniform rescale of " +
                         (dir / "skew" / "cam00" / "0000.png").string() + " (32x24)");
  }
}

TEST_CASE("colmap bad inputs") {
  test::TempDir dir("colmap_errors");
  const data::Dataset ref = synth_reference(dir / "synth");
  const fs::path root = dir / "s", sparse = root / "sparse" / "0";
  const fs::path cameras_bin = sparse / "cameras.bin", images_bin = sparse / "images.bin";
  test::ColmapModel model = test::colmap_from(ref);
  write_fixture(root, ref, model, true);
  REQUIRE(data::load_colmap(root).views.size() == 12);  // every subcase breaks one thing of a good model

  SUBCASE("missing images file") {
    fs::remove(images_bin);
    check_load_fails(root, images_bin, "missing, and so is images.txt");
  }
  SUBCASE("image with an unknown camera id") {
    model.images[1].camera_id = 7;  // image 98 'cam02/images/0000.png'
    test::write_colmap_bin(sparse, model);
    check_load_fails(root, images_bin, "image 98 'cam02/images/0000.png': camera_id 7 is not in cameras.bin");
  }
  SUBCASE("distorted model") {
    model.cameras[2] = {12, 4, "OPENCV", 32, 24, {40, 40, 16, 12, -0.05, 0, 0, 0}};
    test::write_colmap_txt(sparse, model);
    fs::remove(cameras_bin);
    check_load_fails(root, sparse / "cameras.txt", "camera 12 (OPENCV): params: distortion parameter 1 is -0.05");
    CHECK_THROWS_WITH_AS(data::load_colmap(root), doctest::Contains("colmap image_undistorter"), std::runtime_error);
  }
  SUBCASE("fisheye model, even without distortion") {
    model.cameras[0] = {10, 5, "OPENCV_FISHEYE", 32, 24, {40, 40, 16, 12, 0, 0, 0, 0}};
    test::write_colmap_bin(sparse, model);
    check_load_fails(root, cameras_bin, "camera 10 (OPENCV_FISHEYE): model: fisheye projection");
  }
  SUBCASE("unknown model id") {
    model.cameras[1].model_id = 42;
    test::write_colmap_bin(sparse, model);
    check_load_fails(root, cameras_bin, "camera 11: model_id 42 is not a COLMAP camera model");
  }
  SUBCASE("unknown model name in cameras.txt") {
    model.cameras[1].model_name = "PINHOLE_ISH";
    test::write_colmap_txt(sparse, model);
    fs::remove(cameras_bin);
    check_load_fails(root, sparse / "cameras.txt", "line 5: camera 11: model 'PINHOLE_ISH' is not a COLMAP camera model");
  }
  SUBCASE("truncated binary file with a lying count") {
    std::string bytes = test::read_raw(cameras_bin);
    const uint64_t lie = uint64_t{1} << 40;  // would be 48 TiB of cameras if believed
    std::memcpy(&bytes[0], &lie, sizeof lie);
    test::write_raw(cameras_bin, bytes);
    check_load_fails(root, cameras_bin, "camera count: 1099511627776 records need at least 48 bytes each but only");
  }
  SUBCASE("binary file cut short") {
    // The last image (100, cam00) ends "cam00.png\0", num_points2D, 2 x 24 bytes: cut into its name.
    const std::string bytes = test::read_raw(images_bin);
    test::write_raw(images_bin, bytes.substr(0, bytes.size() - 60));
    check_load_fails(root, images_bin, "image 100: name: file truncated");
  }
  SUBCASE("lying 2D point count inside an image") {
    std::string bytes = test::read_raw(images_bin);
    // First image record: id (4), 7 doubles, camera id (4), "cam03.png\0", then num_points2D.
    const size_t at = 8 + 4 + 56 + 4 + 10;
    REQUIRE(bytes.substr(8 + 4 + 56 + 4, 10) == std::string("cam03.png\0", 10));
    const uint64_t lie = ~uint64_t{0};
    std::memcpy(&bytes[at], &lie, sizeof lie);
    test::write_raw(images_bin, bytes);
    check_load_fails(root, images_bin, "image 97: num_points2D: 18446744073709551615 records need at least 24 bytes");
  }
  SUBCASE("bad number in images.txt") {
    test::write_colmap_txt(sparse, model);
    fs::remove(images_bin);
    std::string text = test::read_raw(sparse / "images.txt");
    const size_t at = text.find(" 11 cam01/0000.png");
    REQUIRE(at != std::string::npos);
    text.replace(at, 3, " 1x");
    test::write_raw(sparse / "images.txt", text);
    check_load_fails(root, sparse / "images.txt", "line 8: image 99: camera_id: '1x' is not an integer");
  }
  SUBCASE("zero quaternion") {
    model.images[0].q = {0, 0, 0, 0};
    test::write_colmap_bin(sparse, model);
    check_load_fails(root, images_bin, "image 97 'cam03.png': qvec: zero quaternion");
  }
  SUBCASE("non-finite translation") {
    model.images[0].t[1] = std::nan("");
    test::write_colmap_bin(sparse, model);
    check_load_fails(root, images_bin, "image 97 'cam03.png': tvec: non-finite value");
  }
  SUBCASE("two images map to one frame folder") {
    model.images[0].name = "cam02.png";
    test::write_colmap_bin(sparse, model);
    check_load_fails(root, images_bin, "image 98 'cam02/images/0000.png': name: maps to frame folder 'cam02' like image 97 'cam02.png'");
  }
  SUBCASE("frame count mismatch") {
    fs::remove(root / "cam02" / "0002.png");
    check_load_fails(root, root / "cam02", "has 2 frames but cam00 has 3: missing 0002.png (frame 2 of cam00); every camera "
                                           "needs the same frame count");
  }
  SUBCASE("missing frame folder") {
    fs::remove_all(root / "cam01");
    check_load_fails(root, root / "cam01", "missing: the frame folder of image 99 'cam01/0000.png' in " + images_bin.string());
  }
  SUBCASE("bad points3D.txt") {
    fs::remove(sparse / "points3D.bin");
    test::write_raw(sparse / "points3D.txt", "# comment\n1 0.5 0.5 0.5 255 0 300 0.1\n");
    check_load_fails(root, sparse / "points3D.txt", "line 2: point 1: rgb: 300 is out of range [0, 255]");
  }
}
