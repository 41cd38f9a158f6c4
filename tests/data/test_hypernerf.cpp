// HyperNeRF / Nerfies loading: the built-in scene, loaded through the DyNeRF and D-NeRF loaders as the
// reference, is rewritten in the HyperNeRF layout by test code (hypernerf_fixture.h) and must come back
// as the same views, up to scene.json's normalisation (centre -> (centre - center) * scale).
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>

#include "hypernerf_fixture.h"
#include "s4d/data/frame_cache.h"
#include "s4d/synth/dataset.h"

using namespace s4d;
namespace fs = std::filesystem;

namespace {

// A scene.json that moves and shrinks the world, so the normalisation is exercised.
const test::HyperScene kScene{{0.3, -0.2, 1.5}, 0.25};

Vec3 normalised(const Vec3& p, const test::HyperScene& s) {
  return {(p[0] - s.center[0]) * s.scale, (p[1] - s.center[1]) * s.scale, (p[2] - s.center[2]) * s.scale};
}

// How far a loaded camera is from the reference one moved into the normalised scene: the angle
// (degrees) of the rotation between them, and the largest difference of a centre coordinate.
struct PoseError {
  double degrees = 0, centre = 0;
};

PoseError pose_error(const io::CameraView& loaded, const io::CameraView& reference, const test::HyperScene& s) {
  PoseError e;
  double trace = 0;  // of R_loaded R_reference^T
  for (size_t i = 0; i < 3; ++i) {
    for (size_t k = 0; k < 3; ++k) trace += loaded.world_to_cam[i * 4 + k] * reference.world_to_cam[i * 4 + k];
  }
  e.degrees = std::acos(std::clamp((trace - 1) / 2, -1.0, 1.0)) * 180 / std::acos(-1.0);
  const Vec3 got = test::centre(loaded), want = normalised(test::centre(reference), s);
  for (size_t k = 0; k < 3; ++k) e.centre = std::max(e.centre, std::abs(got[k] - want[k]));
  return e;
}

data::Dataset synth_reference(const fs::path& dir, bool dnerf) {
  synth::write_dataset(dir, {.cams = 4, .frames = 3, .width = 32, .height = 24, .seed = 1, .samples_per_axis = 1,
                             .points = 50, .dnerf = dnerf});
  return dnerf ? data::load_dnerf(dir) : data::load_dynerf(dir);
}

// Checks every view of `loaded` against `reference` (same order) and returns the worst pose error.
PoseError check_against(const data::Dataset& loaded, const data::Dataset& reference, const test::HyperScene& s) {
  REQUIRE(loaded.views.size() == reference.views.size());
  PoseError worst;
  for (size_t i = 0; i < loaded.views.size(); ++i) {
    const data::View &got = loaded.views[i], &want = reference.views[i];
    std::string id = want.name;
    std::replace(id.begin(), id.end(), '/', '_');
    CHECK(got.name == id);
    CHECK(got.test == want.test);
    CHECK(got.camera_index == -1);
    CHECK(got.time == doctest::Approx(want.time).epsilon(1e-12));
    CHECK(got.camera.time == got.time);
    CHECK(got.image == loaded.root / "rgb" / "1x" / (id + ".png"));
    // Intrinsics are written with 17 digits and copied: exact, but for fy = focal * aspect.
    CHECK(got.camera.fx == want.camera.fx);
    CHECK(got.camera.fy == doctest::Approx(want.camera.fy).epsilon(1e-14));
    CHECK(got.camera.cx == want.camera.cx);
    CHECK(got.camera.cy == want.camera.cy);
    CHECK(got.camera.width == want.camera.width);
    CHECK(got.camera.height == want.camera.height);
    const PoseError e = pose_error(got.camera, want.camera, s);
    worst.degrees = std::max(worst.degrees, e.degrees);
    worst.centre = std::max(worst.centre, e.centre);
    // The same world point, normalised, lands on the same pixel.
    for (const Vec3& p : {Vec3{0, 0, 0}, Vec3{0.5, 0.3, -0.2}}) {
      const Vec3 a = test::project(got.camera, normalised(p, s)), b = test::project(want.camera, p);
      CHECK(std::abs(a[0] - b[0]) < 1e-9);
      CHECK(std::abs(a[1] - b[1]) < 1e-9);
    }
  }
  return worst;
}

}  // namespace

TEST_CASE("hypernerf: a DyNeRF scene rewritten as HyperNeRF loads as the same views, normalised") {
  test::TempDir dir("hypernerf_dynerf");
  data::Dataset reference = synth_reference(dir / "synth", false);
  REQUIRE(reference.views.size() == 12);
  // Non-trivial intrinsics: a pixel aspect ratio and an off-centre principal point.
  for (data::View& v : reference.views) v.camera.fy = v.camera.fx * 1.0625, v.camera.cx += 0.75, v.camera.cy -= 0.5;
  test::write_hypernerf(dir / "hyper", test::hyper_items(reference, 3), kScene);

  const data::Dataset d = data::load_hypernerf(dir / "hyper");
  CHECK(d.kind == "hypernerf");
  CHECK(d.layout == "hypernerf");
  CHECK(d.downscale == 1);
  CHECK(d.background == std::array<float, 3>{1, 1, 1});
  CHECK(data::load_dataset(dir / "hyper").layout == "hypernerf");  // detected by its dataset.json
  const PoseError worst = check_against(d, reference, kScene);
  // Measured: 1.7e-6 degrees (the rotation is copied; that is acos's resolution near 1), centre
  // 1.1e-16 (-R c and back in doubles).
  CHECK(worst.degrees < 1e-5);
  CHECK(worst.centre < 1e-12);
  // The same training cameras (cam00 held out), shrunk by the scale.
  CHECK(d.extent == doctest::Approx(reference.extent * kScene.scale).epsilon(1e-12));

  // The frames are the reference's, read unchanged.
  data::FrameCache ours(d, 1 << 20), theirs(reference, 1 << 20);
  CHECK(ours.get(d.views[5]).data == theirs.get(reference.views[5]).data);
}

TEST_CASE("hypernerf: the D-NeRF monocular scene loads with its split and times") {
  test::TempDir dir("hypernerf_dnerf");
  const data::Dataset reference = synth_reference(dir / "synth", true);
  const test::HyperScene scene{{-1, 0.5, 2}, 2};
  test::write_hypernerf(dir / "hyper", test::hyper_items(reference, 3), scene);
  const data::Dataset d = data::load_hypernerf(dir / "hyper");
  const PoseError worst = check_against(d, reference, scene);
  CHECK(worst.degrees < 1e-5);  // measured 1.7e-6
  CHECK(worst.centre < 1e-12);   // measured 8.9e-16
  CHECK(std::count_if(d.views.begin(), d.views.end(), [](const data::View& v) { return v.test; }) == 3);
}

TEST_CASE("hypernerf: orientation written camera-to-world is caught by the same comparison") {
  test::TempDir dir("hypernerf_transposed");
  const data::Dataset reference = synth_reference(dir / "synth", false);
  test::write_hypernerf(dir / "hyper", test::hyper_items(reference, 3), kScene, false, /*transposed=*/true);
  // Still a rotation, so it loads; only the poses are wrong.
  const data::Dataset d = data::load_hypernerf(dir / "hyper");
  REQUIRE(d.views.size() == reference.views.size());
  PoseError worst;
  double pixels = 0;  // how far the scene centre's image moves
  for (size_t i = 0; i < d.views.size(); ++i) {
    const PoseError e = pose_error(d.views[i].camera, reference.views[i].camera, kScene);
    worst.degrees = std::max(worst.degrees, e.degrees);
    worst.centre = std::max(worst.centre, e.centre);
    const Vec3 a = test::project(d.views[i].camera, normalised({0, 0, 0}, kScene));
    const Vec3 b = test::project(reference.views[i].camera, {0, 0, 0});
    pixels = std::max(pixels, a[2] <= 0 ? 1e9 : std::hypot(a[0] - b[0], a[1] - b[1]));
  }
  // position is the centre whatever the orientation, so only the rotation is off. The synth cameras
  // are near a half turn about x (looking at the origin, y down), which a transpose leaves alone, so
  // the error is only the yaw of the arc, doubled. Measured: 17.0 degrees, and the scene centre's
  // image moved by 10.4 px of a 32 px image (the right convention: 1.7e-6 degrees, under 1e-9 px).
  CHECK(worst.degrees > 5);
  CHECK(pixels > 5);
}

TEST_CASE("hypernerf: downscale box-filters rgb/1x and scales the intrinsics") {
  test::TempDir dir("hypernerf_downscale");
  const data::Dataset reference = synth_reference(dir / "synth", false);
  test::write_hypernerf(dir / "hyper", test::hyper_items(reference, 3), kScene);
  const data::Dataset d = data::load_hypernerf(dir / "hyper", {.downscale = 2, .background = {}});
  CHECK(d.downscale == 2);
  const io::CameraView& c = d.views[0].camera;
  CHECK(c.width == 16);
  CHECK(c.height == 12);
  CHECK(c.fx == reference.views[0].camera.fx / 2);
  CHECK(c.cx == reference.views[0].camera.cx / 2);
  data::FrameCache cache(d, 1 << 20);
  CHECK(cache.get(d.views[0]).width == 16);
}

TEST_CASE("hypernerf: downscale N reads HyperNeRF's own rgb/Nx/ when it is there, unfiltered") {
  test::TempDir dir("hypernerf_prescaled");
  const data::Dataset reference = synth_reference(dir / "synth", false);
  const std::vector<test::HyperItem> items = test::hyper_items(reference, 3);
  test::write_hypernerf(dir / "hyper", items, kScene);
  // rgb/2x/ holds frames unlike anything a box filter of rgb/1x/ gives, so reading them filtered
  // again (8x6) or filtering 1x instead would both fail below.
  std::filesystem::create_directories(dir / "hyper" / "rgb" / "2x");
  for (size_t i = 0; i < items.size(); ++i)
    io::write_png(dir / "hyper" / "rgb" / "2x" / (items[i].id + ".png"), test::pattern(16, 12, 3, static_cast<int>(i)));
  const data::Dataset d = data::load_hypernerf(dir / "hyper", {.downscale = 2, .background = {}});
  for (size_t i = 0; i < d.views.size(); ++i) {
    const data::View& v = d.views[i];
    CHECK(v.image.parent_path().filename() == "2x");
    CHECK(v.file_downscale == 1);
    CHECK(v.camera.width == 16);
    CHECK(v.camera.fx == reference.views[0].camera.fx / 2);
  }
  data::FrameCache cache(d, 1 << 20);
  const io::ImageF& got = cache.get(d.views[0]);
  const io::ImageF want = io::read_png(d.views[0].image);
  CHECK(got.width == 16);
  CHECK(got.data == want.data);
  // A 2x frame of the wrong size is refused naming the camera file and both sizes.
  io::write_png(dir / "hyper" / "rgb" / "2x" / (items[0].id + ".png"), test::pattern(15, 12, 3, 0));
  CHECK_THROWS_WITH_AS(data::load_hypernerf(dir / "hyper", {.downscale = 2, .background = {}}),
                       doctest::Contains("(16x12 at 2x) but"), std::runtime_error);
}

TEST_CASE("hypernerf: without val_ids, every 4th id trains and the middles test (interp captures)") {
  test::TempDir dir("hypernerf_interp");
  const data::Dataset reference = synth_reference(dir / "synth", false);
  std::vector<test::HyperItem> items = test::hyper_items(reference, 3);
  items.resize(11);
  for (size_t i = 0; i < items.size(); ++i) items[i].warp_id = static_cast<long long>(i);
  test::write_hypernerf(dir / "hyper", items, kScene, /*interp=*/true);
  const data::Dataset d = data::load_hypernerf(dir / "hyper");
  // ids 0, 4, 8 train; 2, 6 test (the middles); odd ids and 10 (past the last training id) unused.
  REQUIRE(d.views.size() == 5);
  const size_t used[] = {0, 2, 4, 6, 8};
  for (size_t k = 0; k < 5; ++k) {
    CHECK(d.views[k].name == items[used[k]].id);
    CHECK(d.views[k].test == (used[k] % 4 == 2));
    CHECK(d.views[k].time == doctest::Approx(static_cast<double>(used[k]) / 10));  // warp_id over the largest of all ids
  }
}

TEST_CASE("hypernerf: points.npy and points3D_downsample2.ply are normalised like the cameras") {
  test::TempDir dir("hypernerf_points");
  const data::Dataset reference = synth_reference(dir / "synth", false);
  const fs::path root = dir / "hyper";
  test::write_hypernerf(root, test::hyper_items(reference, 3), kScene);
  const std::vector<Vec3> points = {{1, 2, 3}, {-0.5, 0.25, 4}};
  data::write_npy(root / "points.npy", {{2, 3}, {1, 2, 3, -0.5, 0.25, 4}});
  data::Dataset d = data::load_hypernerf(root);
  CHECK(d.points_file == root / "points.npy");
  REQUIRE(d.points.size() == 6);
  for (size_t i = 0; i < 2; ++i) {
    const Vec3 want = normalised(points[i], kScene);
    for (size_t k = 0; k < 3; ++k) CHECK(d.points[i * 3 + k] == doctest::Approx(want[k]).epsilon(1e-6));  // float32
  }
  CHECK(d.colors == std::vector<float>(6, 0.5f));

  // 4DGaussians' COLMAP cloud wins when both are there; it is in the raw frame too.
  test::write_raw(root / "points3D_downsample2.ply",
                  "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n"
                  "property uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n0.3 -0.2 5.5 255 0 0\n");
  d = data::load_hypernerf(root);
  CHECK(d.points_file == root / "points3D_downsample2.ply");
  REQUIRE(d.points.size() == 3);
  CHECK(d.points[0] == doctest::Approx(0).epsilon(1e-6));
  CHECK(d.points[1] == doctest::Approx(0).epsilon(1e-6));
  CHECK(d.points[2] == doctest::Approx(1).epsilon(1e-6));  // (5.5 - 1.5) * 0.25
}

TEST_CASE("hypernerf: bad input is refused naming the file and the field") {
  test::TempDir dir("hypernerf_errors");
  const data::Dataset reference = synth_reference(dir / "synth", false);
  const std::vector<test::HyperItem> items = test::hyper_items(reference, 3);
  const fs::path root = dir / "hyper";
  const std::string id = items[1].id;  // "cam00_0001"
  const fs::path camera = root / "camera" / (id + ".json");
  auto fresh = [&] {
    fs::remove_all(root);
    test::write_hypernerf(root, items, kScene);
  };
  // Rewrites camera/ID.json with one field replaced.
  auto with_field = [&](const std::string& key, const std::string& value) {
    fresh();
    test::JsonFields f = test::hyper_camera_fields(items[1].camera);
    f[key] = value;
    test::write_raw(camera, test::json_object(f));
  };
  auto load = [&] { return data::load_hypernerf(root); };

  fresh();
  fs::remove(root / "dataset.json");
  CHECK_THROWS_WITH_AS(load(), test::error_at(root / "dataset.json", "missing"), std::runtime_error);

  fresh();
  fs::remove(camera);
  CHECK_THROWS_WITH_AS(load(), test::error_at(root / "dataset.json", "ids[1]: '" + id + "' has no camera file"), std::runtime_error);

  fresh();
  fs::remove(root / "rgb" / "1x" / (id + ".png"));
  CHECK_THROWS_WITH_AS(load(), test::error_at(root / "dataset.json", "ids[1]: '" + id + "' has no image"), std::runtime_error);

  with_field("orientation", "[[2, 0, 0], [0, 2, 0], [0, 0, 2]]");
  CHECK_THROWS_WITH_AS(load(), test::error_at(camera, "orientation: not a rotation"), std::runtime_error);

  with_field("orientation", "[[1, 0, 0], [0, 1, 0]]");
  CHECK_THROWS_WITH_AS(load(), test::error_at(camera, "orientation: must be 3 rows"), std::runtime_error);

  // JSON cannot spell a non-finite number: what Python writes for one, and an overflowing exponent, are
  // parse errors (the loader's own finiteness check is a second line).
  with_field("position", "[0, NaN, 0]");
  CHECK_THROWS_WITH_AS(load(), test::error_at(camera, "not valid JSON"), std::runtime_error);
  with_field("position", "[0, 1e999, 0]");
  CHECK_THROWS_WITH_AS(load(), test::error_at(camera, "not valid JSON"), std::runtime_error);

  with_field("focal_length", "0");
  CHECK_THROWS_WITH_AS(load(), test::error_at(camera, "focal_length: must be > 0"), std::runtime_error);

  with_field("image_size", "[34, 24]");
  CHECK_THROWS_WITH_AS(load(), test::error_at(camera, "image_size: says 34x24 but"), std::runtime_error);

  with_field("skew", "0.5");
  CHECK_THROWS_WITH_AS(load(), test::error_at(camera, "skew: must be 0"), std::runtime_error);

  with_field("radial_distortion", "[0.3, 0, 0]");
  CHECK_THROWS_WITH_AS(load(), test::error_at(camera, "radial_distortion / tangential_distortion: move the image border by"),
                       std::runtime_error);
  with_field("radial_distortion", "[0.0001, 0, 0]");  // what real captures carry is ignored, as 4DGaussians does
  CHECK_NOTHROW(load());

  with_field("focal_length", "\"ten\"");
  CHECK_THROWS_WITH_AS(load(), test::error_at(camera, "focal_length: must be a number"), std::runtime_error);

  fresh();
  test::write_raw(root / "metadata.json", "{\"" + items[0].id + "\": {\"warp_id\": 0}}");
  CHECK_THROWS_WITH_AS(load(), test::error_at(root / "metadata.json", id + ": missing"), std::runtime_error);

  fresh();
  test::write_raw(root / "metadata.json", test::json_object({{items[0].id, "{\"warp_id\": 0}"}, {id, "{\"camera_id\": 0}"}}));
  CHECK_THROWS_WITH_AS(load(), test::error_at(root / "metadata.json", id + ".warp_id: missing"), std::runtime_error);

  fresh();
  test::write_raw(root / "dataset.json", "{\"ids\": [\"" + items[0].id + "\"], \"train_ids\": [], \"val_ids\": [\"nope\"]}");
  CHECK_THROWS_WITH_AS(load(), test::error_at(root / "dataset.json", "val_ids[0]: 'nope' is not in ids"), std::runtime_error);

  fresh();
  test::write_raw(root / "dataset.json", "{\"ids\": [\"../x\"], \"train_ids\": [], \"val_ids\": []}");
  CHECK_THROWS_WITH_AS(load(), test::error_at(root / "dataset.json", "ids[0]: '../x' is not a plain file name"), std::runtime_error);

  fresh();
  test::write_raw(root / "scene.json", "{\"scale\": -1, \"center\": [0, 0, 0]}");
  CHECK_THROWS_WITH_AS(load(), test::error_at(root / "scene.json", "scale: must be > 0"), std::runtime_error);

  fresh();
  test::write_raw(root / "scene.json", "{\"scale\": 1, \"center\": [0, 0]");
  CHECK_THROWS_WITH_AS(load(), test::error_at(root / "scene.json", "not valid JSON"), std::runtime_error);
}
