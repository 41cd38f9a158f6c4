// Writes COLMAP sparse models (cameras / images / points3D, .bin and .txt) from test code, following
// COLMAP's documented formats and conventions independently of the loader: qvec (w, x, y, z) and
// tvec are the world-to-camera rotation and translation, binary files little endian. A model can be
// built from a loaded reference dataset (one COLMAP image per rig camera) and then altered to
// produce the bad inputs the error tests need.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <iomanip>
#include <sstream>
#include <string>
#include <vector>

#include "data_test_util.h"

namespace s4d::test {

struct ColmapCamera {
  int id = 0;
  int model_id = 1;  // 1 = PINHOLE
  std::string model_name = "PINHOLE";
  uint64_t width = 0, height = 0;
  std::vector<double> params;
};

struct ColmapImage {
  int id = 0;
  std::array<double, 4> q{};  // w, x, y, z
  std::array<double, 3> t{};
  int camera_id = 0;
  std::string name;
};

struct ColmapPoint {
  uint64_t id = 0;
  Vec3 xyz{};
  std::array<uint8_t, 3> rgb{};
};

struct ColmapModel {
  std::vector<ColmapCamera> cameras;
  std::vector<ColmapImage> images;
  std::vector<ColmapPoint> points;
};

// Unit quaternion (w, x, y, z) of a rotation matrix, choosing the largest of 4w^2, 4x^2, 4y^2, 4z^2
// as the pivot so no division is by a small number.
inline std::array<double, 4> quaternion_of(const double r[3][3]) {
  const double d[4] = {1 + r[0][0] + r[1][1] + r[2][2], 1 + r[0][0] - r[1][1] - r[2][2],
                       1 - r[0][0] + r[1][1] - r[2][2], 1 - r[0][0] - r[1][1] + r[2][2]};  // 4w^2, 4x^2, 4y^2, 4z^2
  const int k = static_cast<int>(std::max_element(d, d + 4) - d);
  const double s = 2 * std::sqrt(d[k]);  // 4 |q_k|
  // Off-diagonal sums and differences: r21 - r12 = 4wx, r02 - r20 = 4wy, r10 - r01 = 4wz,
  // r01 + r10 = 4xy, r02 + r20 = 4xz, r12 + r21 = 4yz.
  const double wx = r[2][1] - r[1][2], wy = r[0][2] - r[2][0], wz = r[1][0] - r[0][1];
  const double xy = r[0][1] + r[1][0], xz = r[0][2] + r[2][0], yz = r[1][2] + r[2][1];
  switch (k) {
    case 0: return {s / 4, wx / s, wy / s, wz / s};
    case 1: return {wx / s, s / 4, xy / s, xz / s};
    case 2: return {wy / s, xy / s, s / 4, yz / s};
    default: return {wz / s, xz / s, yz / s, s / 4};
  }
}

// How the fixture writes poses: the COLMAP convention, or one of the mistakes a loader could make.
enum class PoseConvention { colmap, cam_to_world, xyzw };

// Camera c of the reference becomes COLMAP camera 10 + c and image 100 - c (images listed in
// reverse, so the loader must sort by name and match cameras by id). Image names cycle through the
// three accepted forms. `size_scale` multiplies the COLMAP camera's size and intrinsics (COLMAP run
// at another resolution than the frames).
inline ColmapModel colmap_from(const data::Dataset& ref, PoseConvention convention = PoseConvention::colmap,
                               double size_scale = 1) {
  ColmapModel model;
  std::vector<int> seen;
  for (const data::View& v : ref.views) {
    const int c = v.camera_index;
    if (std::find(seen.begin(), seen.end(), c) != seen.end()) continue;  // one image per camera
    seen.push_back(c);
    const io::CameraView& cam = v.camera;
    model.cameras.push_back({10 + c, 1, "PINHOLE", static_cast<uint64_t>(std::lround(cam.width * size_scale)),
                             static_cast<uint64_t>(std::lround(cam.height * size_scale)),
                             {cam.fx * size_scale, cam.fy * size_scale, cam.cx * size_scale, cam.cy * size_scale}});
    const std::string folder = v.name.substr(0, v.name.find('/'));
    const std::string names[3] = {folder + ".png", folder + "/0000.png", folder + "/images/0000.png"};
    double r[3][3];
    Vec3 t{};
    for (size_t i = 0; i < 3; ++i) {
      for (size_t j = 0; j < 3; ++j) r[i][j] = cam.world_to_cam[i * 4 + j];
      t[i] = cam.world_to_cam[i * 4 + 3];
    }
    if (convention == PoseConvention::cam_to_world) {  // write [R^T | -R^T t] instead
      const Vec3 centre = test::centre(cam);
      for (size_t i = 0; i < 3; ++i) {
        for (size_t j = 0; j < 3; ++j) r[i][j] = cam.world_to_cam[j * 4 + i];
      }
      t = centre;
    }
    std::array<double, 4> q = quaternion_of(r);
    if (convention == PoseConvention::xyzw) q = {q[1], q[2], q[3], q[0]};
    model.images.insert(model.images.begin(), ColmapImage{100 - c, q, {t[0], t[1], t[2]}, 10 + c, names[c % 3]});
  }
  for (size_t i = 0; i < ref.points.size() / 3; ++i) {
    ColmapPoint p{i + 1, {ref.points[3 * i], ref.points[3 * i + 1], ref.points[3 * i + 2]}, {}};
    for (size_t k = 0; k < 3; ++k) p.rgb[k] = static_cast<uint8_t>(std::lround(ref.colors[3 * i + k] * 255));
    model.points.push_back(p);
  }
  return model;
}

inline void write_colmap_bin(const std::filesystem::path& sparse, const ColmapModel& m) {
  std::filesystem::create_directories(sparse);
  std::string cams, ims, pts;
  append_le(cams, static_cast<uint64_t>(m.cameras.size()));
  for (const ColmapCamera& c : m.cameras) {
    append_le(cams, static_cast<int32_t>(c.id));
    append_le(cams, static_cast<int32_t>(c.model_id));
    append_le(cams, c.width);
    append_le(cams, c.height);
    for (double p : c.params) append_le(cams, p);
  }
  append_le(ims, static_cast<uint64_t>(m.images.size()));
  for (const ColmapImage& im : m.images) {
    append_le(ims, static_cast<int32_t>(im.id));
    for (double v : im.q) append_le(ims, v);
    for (double v : im.t) append_le(ims, v);
    append_le(ims, static_cast<int32_t>(im.camera_id));
    ims += im.name;
    ims += '\0';
    append_le(ims, static_cast<uint64_t>(2));  // two 2D points, the second without a 3D point
    for (double v : {1.5, 2.5}) append_le(ims, v);
    append_le(ims, static_cast<int64_t>(1));
    for (double v : {3.5, 4.5}) append_le(ims, v);
    append_le(ims, static_cast<int64_t>(-1));
  }
  append_le(pts, static_cast<uint64_t>(m.points.size()));
  for (const ColmapPoint& p : m.points) {
    append_le(pts, p.id);
    for (double v : p.xyz) append_le(pts, v);
    for (uint8_t v : p.rgb) pts += static_cast<char>(v);
    append_le(pts, 0.75);                        // reprojection error
    append_le(pts, static_cast<uint64_t>(p.id % 3));  // track of 0 to 2 entries
    for (uint64_t k = 0; k < p.id % 3; ++k) {
      append_le(pts, static_cast<int32_t>(100 - static_cast<int>(k)));
      append_le(pts, static_cast<int32_t>(0));
    }
  }
  write_raw(sparse / "cameras.bin", cams);
  write_raw(sparse / "images.bin", ims);
  write_raw(sparse / "points3D.bin", pts);
}

inline void write_colmap_txt(const std::filesystem::path& sparse, const ColmapModel& m) {
  std::filesystem::create_directories(sparse);
  std::ostringstream cams, ims, pts;
  for (std::ostringstream* s : {&cams, &ims, &pts}) *s << std::setprecision(17);
  cams << "# Camera list with one line of data per camera:\n#   CAMERA_ID, MODEL, WIDTH, HEIGHT, PARAMS[]\n"
       << "# Number of cameras: " << m.cameras.size() << "\n";
  for (const ColmapCamera& c : m.cameras) {
    cams << c.id << ' ' << c.model_name << ' ' << c.width << ' ' << c.height;
    for (double p : c.params) cams << ' ' << p;
    cams << '\n';
  }
  ims << "# Image list with two lines of data per image:\n"
      << "#   IMAGE_ID, QW, QX, QY, QZ, TX, TY, TZ, CAMERA_ID, NAME\n#   POINTS2D[] as (X, Y, POINT3D_ID)\n";
  for (size_t i = 0; i < m.images.size(); ++i) {
    const ColmapImage& im = m.images[i];
    ims << im.id;
    for (double v : im.q) ims << ' ' << v;
    for (double v : im.t) ims << ' ' << v;
    ims << ' ' << im.camera_id << ' ' << im.name << '\n';
    ims << (i % 2 ? "1.5 2.5 1 3.5 4.5 -1\n" : "\n");  // 2D points: some images have none
  }
  pts << "# 3D point list with one line of data per point:\n"
      << "#   POINT3D_ID, X, Y, Z, R, G, B, ERROR, TRACK[] as (IMAGE_ID, POINT2D_IDX)\n";
  for (const ColmapPoint& p : m.points) {
    pts << p.id << ' ' << p.xyz[0] << ' ' << p.xyz[1] << ' ' << p.xyz[2];
    for (uint8_t v : p.rgb) pts << ' ' << static_cast<int>(v);
    pts << " 0.75";
    for (uint64_t k = 0; k < p.id % 3; ++k) pts << ' ' << 100 - static_cast<int>(k) << " 0";
    pts << '\n';
  }
  write_raw(sparse / "cameras.txt", cams.str());
  write_raw(sparse / "images.txt", ims.str());
  write_raw(sparse / "points3D.txt", pts.str());
}

// Copies every frame of the reference views to ROOT/<cam>/<stem>.png, or ROOT/<cam>/images/<stem>.png.
inline void copy_frames(const data::Dataset& ref, const std::filesystem::path& root, bool images_folder) {
  for (const data::View& v : ref.views) {
    const std::string folder = v.name.substr(0, v.name.find('/'));
    const std::filesystem::path dir = images_folder ? root / folder / "images" : root / folder;
    std::filesystem::create_directories(dir);
    std::filesystem::copy_file(v.image, dir / v.image.filename(), std::filesystem::copy_options::overwrite_existing);
  }
}

}  // namespace s4d::test
