// DyNeRF / Neu3D layout:
//   poses_bounds.npy   N x 17: per camera, LLFF's 3x5 [c2w rotation | centre | (H, W, focal)] row-major,
//                      then near and far (unused: we do not use NDC rays)
//   camNN/NNNN.png     frames of camera NN; cameras sorted by folder name match rows in order
// The rotation columns are in LLFF axes order (down, right, backwards). OpenGL columns (right, up,
// back) are (col1, -col0, col2), so OpenCV (right, down, forward) = (right, -up, -back) = (col1, col0,
// -col2); world_to_cam is the rigid inverse. No recentring or rescaling, as in 4DGaussians.
// cam00 is the held-out test camera (the Neu3D protocol); time = frame / (T - 1).
#include <algorithm>
#include <cmath>
#include <regex>
#include <sstream>

#include "dataset_parts.h"
#include "s4d/data/npy.h"

namespace s4d::data {
namespace {

namespace fs = std::filesystem;
using detail::fail;

// Same tolerance as read_nerf_cameras: float32 or rounded decimals pass, real scale or shear does not.
constexpr double kRigidTolerance = 1e-3;

struct CameraFolder {
  std::string name;  // "cam03"
  std::vector<fs::path> frames;
};

std::vector<CameraFolder> find_cameras(const fs::path& root) {
  const std::regex cam_name("cam[0-9]+");
  std::vector<std::string> folders, videos;
  for (const auto& entry : fs::directory_iterator(root)) {
    const std::string name = entry.path().filename().string();
    if (entry.is_directory() && std::regex_match(name, cam_name)) folders.push_back(name);
    if (entry.is_regular_file() && entry.path().extension() == ".mp4" && std::regex_match(entry.path().stem().string(), cam_name)) {
      videos.push_back(entry.path().stem().string());
    }
  }
  std::sort(videos.begin(), videos.end());
  for (const std::string& v : videos) {
    if (std::find(folders.begin(), folders.end(), v) == folders.end()) {
      fail(root / (v + ".mp4"), "has no frame folder " + v + "/; this build has no video decoder yet, so extract the "
                                "frames first, e.g. mkdir " + v + " && ffmpeg -i " + v + ".mp4 " + v + "/%04d.png");
    }
  }
  std::sort(folders.begin(), folders.end());
  std::vector<CameraFolder> cameras;
  for (const std::string& name : folders) {
    CameraFolder camera{name, {}};
    for (const auto& entry : fs::directory_iterator(root / name)) {
      if (entry.is_regular_file() && entry.path().extension() == ".png") camera.frames.push_back(entry.path());
    }
    std::sort(camera.frames.begin(), camera.frames.end());
    if (camera.frames.empty()) fail(root / name, "no .png frames");
    cameras.push_back(std::move(camera));
  }
  if (cameras.empty()) fail(root, "no camera folders (camNN/) next to poses_bounds.npy");
  for (const CameraFolder& c : cameras) {
    if (c.frames.size() != cameras[0].frames.size()) {
      fail(root / c.name, "has " + std::to_string(c.frames.size()) + " frames but " + cameras[0].name + " has " +
                              std::to_string(cameras[0].frames.size()) + "; every camera needs the same frame count");
    }
  }
  return cameras;
}

// The camera of one poses_bounds row, before downscaling. `field` names the row in errors.
io::CameraView llff_camera(const fs::path& npy, const double* row, const std::string& field) {
  for (int k = 0; k < 17; ++k) {
    if (!std::isfinite(row[k])) fail(npy, field + ": non-finite value at column " + std::to_string(k));
  }
  auto m = [&](int r, int c) { return row[r * 5 + c]; };
  // Columns of the OpenCV camera-to-world rotation: (col1, col0, -col2).
  double r_cv[3][3];
  for (int r = 0; r < 3; ++r) {
    r_cv[r][0] = m(r, 1);
    r_cv[r][1] = m(r, 0);
    r_cv[r][2] = -m(r, 2);
  }
  double worst = 0;
  for (int a = 0; a < 3; ++a) {
    for (int b = 0; b < 3; ++b) {
      double dot = 0;
      for (int r = 0; r < 3; ++r) dot += r_cv[r][a] * r_cv[r][b];
      worst = std::max(worst, std::abs(dot - (a == b ? 1.0 : 0.0)));
    }
  }
  const double det = r_cv[0][0] * (r_cv[1][1] * r_cv[2][2] - r_cv[1][2] * r_cv[2][1]) -
                     r_cv[0][1] * (r_cv[1][0] * r_cv[2][2] - r_cv[1][2] * r_cv[2][0]) +
                     r_cv[0][2] * (r_cv[1][0] * r_cv[2][1] - r_cv[1][1] * r_cv[2][0]);
  if (worst > kRigidTolerance || std::abs(det - 1.0) > kRigidTolerance) {
    fail(npy, field + ": rotation (columns 0-2 of the 3x5 pose) is not orthonormal with determinant +1");
  }
  const double height = m(0, 4), width = m(1, 4), focal = m(2, 4);
  if (!(height >= 1 && width >= 1 && focal > 0)) fail(npy, field + ": hwf (column 4) must have H, W >= 1 and focal > 0");

  io::CameraView camera;
  // world_to_cam = [R^T | -R^T c] with c the camera centre (column 3).
  for (int i = 0; i < 3; ++i) {
    double t = 0;
    for (int r = 0; r < 3; ++r) {
      camera.world_to_cam[static_cast<size_t>(i * 4 + r)] = r_cv[r][i];
      t -= r_cv[r][i] * m(r, 3);
    }
    camera.world_to_cam[static_cast<size_t>(i * 4 + 3)] = t;
  }
  camera.world_to_cam[15] = 1;
  camera.fx = camera.fy = focal;
  camera.cx = width / 2;
  camera.cy = height / 2;
  return camera;  // width and height come from the frames, which the caller checks against hwf
}

// Shortest form of a number for messages ("2704", "12.5").
std::string num(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

}  // namespace

Dataset load_dynerf(const fs::path& root, const LoadOptions& options) {
  const int factor = detail::checked_downscale(root, options);
  const fs::path npy = root / "poses_bounds.npy";
  if (!fs::exists(npy)) fail(npy, "missing (a DyNeRF / Neu3D dataset needs it)");
  const NpyArray poses = read_npy(npy);
  if (poses.shape.size() != 2 || poses.shape[1] != 17) fail(npy, "shape must be (N, 17)");
  const std::vector<CameraFolder> cameras = find_cameras(root);
  if (poses.shape[0] != cameras.size()) {
    fail(npy, "shape has " + std::to_string(poses.shape[0]) + " rows but there are " + std::to_string(cameras.size()) +
                  " camera folders (" + cameras.front().name + " ... " + cameras.back().name + ")");
  }

  Dataset dataset;
  dataset.kind = "dynerf";
  dataset.root = root;
  const size_t frame_count = cameras[0].frames.size();
  for (size_t c = 0; c < cameras.size(); ++c) {
    const std::string field = "row " + std::to_string(c) + " (" + cameras[c].name + ")";
    io::CameraView camera = llff_camera(npy, &poses.values[c * 17], field);
    // hwf must describe the frames on disk; compare after downscaling, allowing for rounding.
    const auto [w, h] = detail::png_size(cameras[c].frames[0]);
    const double hwf_w = poses.values[c * 17 + 9], hwf_h = poses.values[c * 17 + 4];
    if (std::abs(detail::downscaled(w, factor) - hwf_w / factor) > 1 ||
        std::abs(detail::downscaled(h, factor) - hwf_h / factor) > 1) {
      fail(npy, field + ": hwf says " + num(hwf_w) + "x" + num(hwf_h) + " (W x H) but " +
                    cameras[c].frames[0].string() + " is " + std::to_string(w) + "x" + std::to_string(h));
    }
    camera.width = w;
    camera.height = h;
    detail::downscale_camera(camera, factor);
    for (size_t f = 0; f < frame_count; ++f) {
      View view;
      view.name = cameras[c].name + "/" + cameras[c].frames[f].stem().string();
      view.camera = camera;
      view.camera.name = view.name;
      view.camera.file_path = fs::relative(cameras[c].frames[f], root).string();
      view.time = frame_count > 1 ? static_cast<double>(f) / static_cast<double>(frame_count - 1) : 0.0;
      view.camera.time = view.time;
      view.camera_index = static_cast<int>(c);
      view.image = cameras[c].frames[f];
      view.test = c == 0;
      dataset.views.push_back(std::move(view));
    }
  }
  detail::finish_dataset(dataset, options, {0.0f, 0.0f, 0.0f});
  return dataset;
}

}  // namespace s4d::data
