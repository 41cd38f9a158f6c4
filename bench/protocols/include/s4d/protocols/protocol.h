// Render protocols (ARCHITECTURE.md "[render]"): the frames a trained scene is rendered at, as
// camera + time per frame, grouped into sequences (one video each).
//
//   test       one sequence per test camera, fixed at that camera, at every test-view time (sorted,
//              distinct). DyNeRF / Neu3D: cam00 over its frames. D-NeRF, where every test view has its
//              own pose: each test view's camera over all test-view times.
//   spiral     one sequence around the scene while time runs over [0, 1] (camera_rig.h).
//   train:CAM  one sequence fixed at training camera CAM (camera_name below: "cam03" for DyNeRF,
//              "train_r_005" for D-NeRF) at every training-view time of that camera (D-NeRF: of all
//              training views).
//   FILE.json  one sequence along a camera path with a time per frame: a transforms.json as the
//              viewer records it (R, or view --record) and io::write_nerf_cameras writes; each frame
//              gives its camera (transform_matrix, fl_x, fl_y, cx, cy, w, h) and "time" in [0, 1]
//              (docs/protocols.md, "Camera paths").
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "s4d/data/dataset.h"
#include "s4d/io/nerf_cameras.h"

namespace s4d::protocols {

struct ProtocolFrame {
  int index = 0;          // position in its sequence
  double time = 0;        // in [0, 1], what the scene source is asked for
  io::CameraView camera;  // pose (world_to_cam, OpenCV axes) and intrinsics; name unused
};

struct Sequence {
  std::string name;  // "cam00", "test_r_000", "spiral", ...
  std::vector<ProtocolFrame> frames;
};

struct PathSpec {
  enum class Kind { test, spiral, train, file };
  Kind kind = Kind::test;
  std::string camera;  // train:CAM's CAM
  std::filesystem::path file;  // FILE.json
  std::string text() const;  // "test", "spiral", "train:CAM", the file's path
};

// Parses "test", "spiral", "train:CAM" or a path ending in .json; std::invalid_argument naming the
// accepted forms otherwise.
PathSpec parse_path(const std::string& text);

inline constexpr int kDefaultSpiralFrames = 120;  // LLFF's render_path_spiral default N_views

// The sequences of a path over `dataset`. `spiral_frames` (>= 1) is the spiral's frame count.
// Throws std::invalid_argument when the dataset has no test views (test), no training camera named
// CAM (the message lists them), or a rig the spiral cannot be built from (camera_rig.h); a camera
// path file is read as read_nerf_cameras reads it (std::runtime_error naming the file, frame and
// field), and a frame without a time is refused.
std::vector<Sequence> build_protocol(const data::Dataset& dataset, const PathSpec& path, int spiral_frames);

// The physical camera a view belongs to: the camera folder for DyNeRF ("cam03"); for D-NeRF, where
// each view has its own pose, the view's name with '/' as '_' ("train_r_005", "test_r_000").
std::string camera_name(const data::View& view);

}  // namespace s4d::protocols
