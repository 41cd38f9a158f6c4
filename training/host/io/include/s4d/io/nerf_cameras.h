// Camera files in the NeRF / instant-ngp / D-NeRF "transforms.json" layout: a 'frames' array whose
// entries give file_path and transform_matrix (camera-to-world, OpenGL/Blender axes: x right,
// y up, z backward), with intrinsics given globally and/or per frame.
#pragma once
#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace s4d::io {

struct CameraView {
  // Last component of file_path without its extension ("./test/r_000" -> "r_000"); unique.
  std::string name;
  // Row-major 4x4 world-to-camera in OpenCV axes (x right, y down, z forward): a world point p
  // maps to camera coordinates R p + t, and pixel u = fx * x / z + cx, v = fy * y / z + cy.
  std::array<double, 16> world_to_cam{};
  double fx = 0, fy = 0, cx = 0, cy = 0;  // pixels
  int width = 0, height = 0;              // pixels
  std::optional<double> time;             // in [0, 1], for dynamic scenes
  std::string file_path;                  // as written in the file
};

// Reads a transforms.json. Intrinsics come from the keys camera_angle_x (horizontal field of view,
// radians), camera_angle_y, fl_x, fl_y, cx, cy, w, h, each either global or per frame (per-frame
// wins; at the same level fl_x wins over camera_angle_x). fy defaults to fx, cx to w/2, cy to h/2.
// `default_size` = (width, height) is used when no w/h is given (D-NeRF files have none; the loader
// passes the image size). Throws std::runtime_error naming the file, the frame and the field:
// malformed JSON (with the parser's position), missing 'frames', a transform_matrix that is not 4x4
// numbers or whose 3x3 part is not a rotation within 1e-3 (scaled matrices are rejected), missing
// focal length or size, non-finite or non-positive values, time outside [0, 1], duplicate names.
std::vector<CameraView> read_nerf_cameras(const std::filesystem::path& transforms_json,
                                          std::optional<std::pair<int, int>> default_size = {});

// Writes views as a transforms.json (per frame: file_path, transform_matrix, fl_x, fl_y, cx, cy,
// w, h and time if set) that read_nerf_cameras reads back, replacing `path` atomically.
// Throws std::invalid_argument for a view with an empty file_path or a non-finite value.
void write_nerf_cameras(const std::filesystem::path& path, const std::vector<CameraView>& views);

}  // namespace s4d::io
