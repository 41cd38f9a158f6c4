// COLMAP's sparse model files (cameras, images, points3D; .bin or .txt) parsed into plain structs,
// with no interpretation: the loader (colmap.cpp) decides which camera models and poses it accepts.
// Formats as COLMAP documents them (doc/format.rst, "Output Format"); binary files are little endian:
//   cameras.bin   uint64 count; per camera: int32 id, int32 model_id, uint64 width, uint64 height,
//                 double params[n], n fixed by the model
//   images.bin    uint64 count; per image: int32 id, double qw, qx, qy, qz, tx, ty, tz, int32 camera_id,
//                 NUL-terminated name, uint64 n, n x (double x, double y, int64 point3D_id)
//   points3D.bin  uint64 count; per point: uint64 id, double x, y, z, uint8 r, g, b, double error,
//                 uint64 n, n x (int32 image_id, int32 point2D_idx)
// The .txt forms hold the same fields, one record per line ('#' starts a comment line); images.txt
// gives each image two lines, the second (its 2D points, possibly empty) is skipped.
// Every parse error names the file and the record: "FILE: image 3: camera_id: not an integer".
#pragma once
#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "s4d/util/vec3.h"

namespace s4d::data::colmap {

struct CameraModel {
  int id;
  const char* name;  // COLMAP's spelling, as in cameras.txt
  int num_params;
  bool single_focal;  // params start f, cx, cy (else fx, fy, cx, cy); the rest is distortion
  bool fisheye;       // not a pinhole projection even with zero distortion
};

// nullptr when COLMAP has no such model.
const CameraModel* camera_model(int id);
const CameraModel* camera_model(const std::string& name);

struct Camera {
  int id = 0;
  const CameraModel* model = nullptr;  // never null after parsing
  uint64_t width = 0, height = 0;
  std::vector<double> params;  // model->num_params values
};

struct Image {
  int id = 0;
  std::array<double, 4> q{};  // qw, qx, qy, qz as stored (not normalised): world-to-camera rotation
  Vec3 t{};  // world-to-camera translation
  int camera_id = 0;
  std::string name;  // relative image path, '/'-separated
};

struct Point {
  Vec3 xyz{};
  std::array<uint8_t, 3> rgb{};
};

// Each reads `path`, choosing the format by its extension (.bin or .txt), and throws
// std::runtime_error("<path>: <record>: <field>: <why>") on any malformed or truncated content.
std::vector<Camera> read_cameras(const std::filesystem::path& path);
std::vector<Image> read_images(const std::filesystem::path& path);
std::vector<Point> read_points3d(const std::filesystem::path& path);

}  // namespace s4d::data::colmap
