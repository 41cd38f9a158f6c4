// Every bad input gives a std::runtime_error naming the file and the field at fault.
#include <doctest/doctest.h>

#include "data_test_util.h"
#include "s4d/data/frame_cache.h"

using namespace s4d;
namespace fs = std::filesystem;

namespace {

void check_load_fails(const fs::path& root, const std::string& expected) {
  CHECK_THROWS_WITH_AS(data::load_dataset(root), doctest::Contains(expected.c_str()), std::runtime_error);
}

}  // namespace

TEST_CASE("dataset layout and option errors") {
  test::TempDir dir("errors_layout");
  fs::create_directories(dir / "empty");
  check_load_fails(dir / "empty", "unknown dataset layout: found none of poses_bounds.npy (DyNeRF / Neu3D), "
                                  "transforms_train.json (D-NeRF), dataset.json (HyperNeRF / Nerfies), sparse/0/ (COLMAP)");
  check_load_fails(dir / "nowhere", "nowhere: not a directory");
  CHECK_THROWS_WITH_AS(data::load_dynerf(dir / "empty"), test::error_at(dir / "empty" / "poses_bounds.npy", "missing"),
                       std::runtime_error);
  test::write_dynerf(dir / "s", test::dynerf_cameras(), 1);
  CHECK_THROWS_WITH_AS(data::load_dataset(dir / "s", {.downscale = 0, .background = {}}),
                       test::error_at(dir / "s", "downscale must be >= 1"), std::runtime_error);
}

TEST_CASE("dynerf bad inputs") {
  test::TempDir dir("errors_dynerf");
  const auto root = dir / "s";
  const auto npy = root / "poses_bounds.npy";
  auto cams = test::dynerf_cameras();
  test::write_dynerf(root, cams, 2);  // few frames: every subcase writes the scene afresh

  SUBCASE("wrong shape") {
    data::write_npy(npy, {{3, 15}, std::vector<double>(45, 1.0)});
    check_load_fails(root, npy.string() + ": shape must be (N, 17)");
  }
  SUBCASE("rows do not match camera folders") {
    test::write_poses_bounds(npy, {cams[0], cams[1]});
    check_load_fails(root, npy.string() + ": shape has 2 rows but there are 3 cameras (cam00 ... cam02)");
  }
  SUBCASE("non-finite pose") {
    cams[1].centre[2] = std::nan("");
    test::write_poses_bounds(npy, cams);
    check_load_fails(root, npy.string() + ": row 1 (cam01): non-finite value at column 13");
  }
  SUBCASE("rotation not orthonormal") {
    cams[2].right = {2, 0, 0};
    test::write_poses_bounds(npy, cams);
    check_load_fails(root, npy.string() + ": row 2 (cam02): rotation");
  }
  SUBCASE("reflection instead of rotation") {
    cams[2].back = {-cams[2].back[0], -cams[2].back[1], -cams[2].back[2]};
    test::write_poses_bounds(npy, cams);
    check_load_fails(root, npy.string() + ": row 2 (cam02): rotation");
  }
  SUBCASE("hwf disagrees with the frames") {
    cams[1].width = 20;
    test::write_poses_bounds(npy, cams);
    check_load_fails(root, npy.string() + ": row 1 (cam01): hwf says 20x12 (W x H) but " +
                               (root / "cam01" / "0000.png").string() + " is 16x12");
  }
  SUBCASE("hwf within rounding of the downscaled frames is accepted") {
    cams[1].width = 17;  // 8.5 after downscale 2; the frames give 8
    test::write_poses_bounds(npy, cams);
    CHECK(data::load_dynerf(root, {.downscale = 2, .background = {}}).views[2].camera.width == 8);
  }
  SUBCASE("cameras with different frame counts") {
    fs::remove(root / "cam02" / "0001.png");
    check_load_fails(root, (root / "cam02").string() + ": has 1 frames but cam00 has 2: missing 0001.png (frame 1 of cam00); "
                           "every camera needs the same frame count");
  }
  SUBCASE("camera folder without frames") {
    for (int f = 0; f < 2; ++f) fs::remove(root / "cam01" / ("000" + std::to_string(f) + ".png"));
    check_load_fails(root, (root / "cam01").string() + ": no .png frames");
  }
  SUBCASE("first frame is not a PNG") {
    test::write_raw(root / "cam01" / "0000.png", "garbage");
    check_load_fails(root, (root / "cam01" / "0000.png").string() + ": not a PNG file");
  }
  SUBCASE("unreadable frame found when it is loaded") {
    const data::Dataset d = data::load_dynerf(root);
    data::FrameCache cache(d, 1 << 20);
    test::write_raw(root / "cam01" / "0000.png", "garbage");
    CHECK_THROWS_WITH_AS(cache.get(d.views[2]), doctest::Contains((root / "cam01" / "0000.png").string().c_str()),
                         std::runtime_error);
    fs::remove(root / "cam01" / "0001.png");
    CHECK_THROWS_WITH_AS(cache.get(d.views[3]), doctest::Contains((root / "cam01" / "0001.png").string().c_str()),
                         std::runtime_error);
  }
  SUBCASE("frame of the wrong size") {
    const data::Dataset d = data::load_dynerf(root);
    io::write_png(root / "cam02" / "0001.png", test::pattern(10, 12, 3, 0));
    data::FrameCache cache(d, 1 << 20);
    CHECK_THROWS_WITH_AS(cache.get(d.views[5]),
                         test::error_at(root / "cam02" / "0001.png",
                                        "image is 10x12 after downscale 1, but view 'cam02/0001' expects 16x12"),
                         std::runtime_error);
  }
  SUBCASE("point cloud without colours: grey; with only some of them: refused") {
    test::write_raw(root / "points3D.ply",
                    "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n"
                    "end_header\n1 2 3\n");
    const data::Dataset d = data::load_dataset(root);
    CHECK(d.points == std::vector<float>{1, 2, 3});
    CHECK(d.colors == std::vector<float>{0.5f, 0.5f, 0.5f});
    test::write_raw(root / "points3D.ply",
                    "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n"
                    "property uchar red\nend_header\n1 2 3 4\n");
    check_load_fails(root, (root / "points3D.ply").string() + ": vertex has some of red, green, blue but not all");
  }
  SUBCASE("point cloud in double precision, 4DGaussians' points3D_downsample2.ply name") {
    fs::remove(root / "points3D.ply");
    test::write_raw(root / "points3D_downsample2.ply",
                    "ply\nformat ascii 1.0\nelement vertex 1\nproperty double x\nproperty double y\nproperty double z\n"
                    "property uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n1.5 2 3 255 0 51\n");
    const data::Dataset d = data::load_dataset(root);
    CHECK(d.points_file == root / "points3D_downsample2.ply");
    CHECK(d.points == std::vector<float>{1.5f, 2, 3});
    CHECK(d.colors == std::vector<float>{1.0f, 0.0f, 0.2f});
  }
  SUBCASE("point cloud with a malformed value") {
    test::write_raw(root / "points3D.ply",
                    "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n"
                    "property uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n1 2 3 4 5 300\n");
    check_load_fails(root, (root / "points3D.ply").string() + ": vertex 0: malformed or out-of-range number");
  }
  SUBCASE("point cloud truncated") {
    test::write_raw(root / "points3D.ply",
                    "ply\nformat binary_little_endian 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
                    "property float z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n"
                    "0123456789abcde");
    check_load_fails(root, (root / "points3D.ply").string() + ": truncated: 2 vertices declared, at most 1 present");
  }
}

TEST_CASE("dynerf video bad inputs") {
  test::TempDir dir("errors_video");
  const auto root = dir / "s";
  auto cams = test::dynerf_cameras();
  test::write_dynerf_videos(root, cams);
  const auto video = root / "cam01.mp4";

  SUBCASE("not a video") {
    test::write_raw(video, "not really a video");
    check_load_fails(root, video.string() + ": cannot open the video");
  }
  SUBCASE("truncated video") {
    // FFmpeg's mp4 muxer writes the index (moov) last, so a cut-off file has none and cannot be opened.
    const std::string bytes = test::read_raw(video);
    test::write_raw(video, bytes.substr(0, bytes.size() / 2));
    check_load_fails(root, video.string() + ": cannot open the video");
  }
  SUBCASE("cameras with different frame counts") {
    test::write_dynerf_videos(root, cams, {4, 4, 3});
    check_load_fails(root, (root / "cam02.mp4").string() + ": has 3 frames but cam00 has 4");
  }
  SUBCASE("hwf disagrees with the video") {
    cams[1].height = 20;
    test::write_poses_bounds(root / "poses_bounds.npy", cams);
    check_load_fails(root, (root / "poses_bounds.npy").string() + ": row 1 (cam01): hwf says 16x20 (W x H) but " +
                               video.string() + " is 16x12");
  }
  SUBCASE("video gone or replaced when its frames are loaded") {
    const data::Dataset d = data::load_dynerf(root);
    data::FrameCache cache(d, 1 << 20);
    data::View past_end = d.views[4];  // cam01, frame 0
    past_end.frame_in_file = 9;
    CHECK_THROWS_WITH_AS(cache.get(past_end), test::error_at(video, "frame 9 cannot be decoded"), std::runtime_error);
    test::write_raw(video, "garbage");
    CHECK_THROWS_WITH_AS(cache.get(d.views[5]), test::error_at(video, "cannot open the video"), std::runtime_error);
    std::filesystem::remove(video);
    CHECK_THROWS_WITH_AS(cache.get(d.views[6]), test::error_at(video, "video does not exist"), std::runtime_error);
  }
  SUBCASE("video frames of the wrong size") {
    const data::Dataset d = data::load_dynerf(root);
    {
      data::VideoWriter smaller(video, 10, 12);
      for (int f = 0; f < 4; ++f) smaller.write(test::smooth_pattern(10, 12, f));
    }
    data::FrameCache cache(d, 1 << 20);
    CHECK_THROWS_WITH_AS(cache.get(d.views[5]),
                         test::error_at(video, "frame 1 is 10x12 after downscale 1, but view 'cam01/0001' expects 16x12"),
                         std::runtime_error);
  }
}

TEST_CASE("video writer refuses odd sizes and unwritable paths, naming the file") {
  test::TempDir dir("errors_video_writer");
  CHECK_THROWS_WITH_AS(data::VideoWriter(dir / "a.mp4", 15, 12),
                       test::error_at(dir / "a.mp4", "video size must be even on both sides"), std::invalid_argument);
  CHECK_THROWS_WITH_AS(data::VideoWriter(dir / "no" / "such" / "dir.mp4", 16, 12),
                       test::error_at(dir / "no" / "such" / "dir.mp4", "cannot open an mp4v"), std::runtime_error);
  data::VideoWriter video(dir / "b.mp4", 16, 12);
  CHECK_THROWS_WITH_AS(video.write(test::smooth_pattern(16, 10, 0)),
                       test::error_at(dir / "b.mp4", "frame is 16x10x3"), std::invalid_argument);
}

TEST_CASE("dnerf bad inputs") {
  test::TempDir dir("errors_dnerf");
  const auto root = dir / "s";
  fs::create_directories(root / "train");
  io::write_png(root / "train" / "r_000.png", test::pattern(4, 4, 4, 0));
  const std::string identity = "[[1,0,0,0],[0,1,0,0],[0,0,1,4],[0,0,0,1]]";
  auto json = [&](const std::string& frame_extra) {
    return R"({"camera_angle_x": 1.0, "frames": [{"file_path": "./train/r_000", )" + frame_extra +
           R"("transform_matrix": )" + identity + "}]}";
  };
  test::write_raw(root / "transforms_train.json", json("\"time\": 0.5, "));

  SUBCASE("missing test split") {
    check_load_fails(root, (root / "transforms_test.json").string() + ": missing");
  }
  test::write_raw(root / "transforms_test.json", json("\"time\": 0.5, "));
  SUBCASE("missing time") {
    test::write_raw(root / "transforms_test.json", json(""));
    check_load_fails(root, (root / "transforms_test.json").string() + ": frames[0].time: missing");
  }
  SUBCASE("time outside [0, 1]") {
    test::write_raw(root / "transforms_train.json", json("\"time\": 1.5, "));
    check_load_fails(root, (root / "transforms_train.json").string() + ": frames[0].time");
  }
  SUBCASE("image named by the first frame does not exist") {
    test::write_raw(root / "transforms_train.json",
                    R"({"camera_angle_x": 1.0, "frames": [{"file_path": "./train/r_009", "time": 0, "transform_matrix": )" +
                        identity + "}]}");
    check_load_fails(root, (root / "transforms_train.json").string() + ": frames[0].file_path: image " +
                               (root / "train" / "r_009.png").string() + " does not exist");
  }
  SUBCASE("a file_path outside the dataset folder: refused, never followed") {
    for (const std::string path : {"../../etc/passwd", "/etc/passwd", "./train/../../outside"}) {
      test::write_raw(root / "transforms_train.json",
                      R"({"camera_angle_x": 1.0, "frames": [{"file_path": ")" + path + R"(", "time": 0, "transform_matrix": )" +
                          identity + "}]}");
      check_load_fails(root, (root / "transforms_train.json").string() + ": frames[0].file_path: '" + path +
                                 "' is not inside the dataset folder");
    }
  }
  SUBCASE("image of a later frame missing: refused at load; of the wrong size: named when it is read") {
    test::write_raw(root / "transforms_train.json",
                    R"({"camera_angle_x": 1.0, "frames": [{"file_path": "./train/r_000", "time": 0, "transform_matrix": )" +
                        identity + R"(}, {"file_path": "./train/r_001", "time": 1, "transform_matrix": )" + identity +
                        "}]}");
    check_load_fails(root, (root / "transforms_train.json").string() + ": frames[1].file_path: image " +
                               (root / "train" / "r_001.png").string() + " does not exist");
    io::write_png(root / "train" / "r_001.png", test::pattern(6, 4, 4, 1));
    const data::Dataset d = data::load_dnerf(root);
    data::FrameCache cache(d, 1 << 20);
    CHECK_THROWS_WITH_AS(cache.get(d.views[1]),
                         test::error_at(root / "train" / "r_001.png",
                                        "image is 6x4 after downscale 1, but view 'train/r_001' expects 4x4"),
                         std::runtime_error);
  }
  SUBCASE("bad background") {
    CHECK_THROWS_WITH_AS(data::load_dnerf(root, {.downscale = 1, .background = std::array<float, 3>{0, 2, 0}}),
                         test::error_at(root, "background components must be in [0, 1]"), std::runtime_error);
  }
  SUBCASE("valid") { CHECK(data::load_dataset(root).views.size() == 2); }
}
