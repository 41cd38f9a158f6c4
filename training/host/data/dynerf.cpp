// DyNeRF / Neu3D layout:
//   poses_bounds.npy   N x 17: per camera, LLFF's 3x5 [c2w rotation | centre | (H, W, focal)] row-major,
//                      then near and far (unused: we do not use NDC rays)
//   camNN/NNNN.png     frames of camera NN; cameras sorted by name match rows in order
//   camNN/images/NNNN.png  the same, as 4DGaussians' preprocessing writes them (used when camNN/ has no
//                      .png of its own); its point cloud points3D_downsample2.ply
//   camNN.mp4          or camera NN as one video, used when there is no camNN/ folder (a folder wins:
//                      its PNGs are lossless); the frame count is the one the container declares
// The rotation columns are in LLFF axes order (down, right, backwards). OpenGL columns (right, up,
// back) are (col1, -col0, col2), so OpenCV (right, down, forward) = (right, -up, -back) = (col1, col0,
// -col2); world_to_cam is the rigid inverse. No recentring or rescaling, as in 4DGaussians.
// cam00 is the held-out test camera (the Neu3D protocol); time = frame / (T - 1).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <regex>
#include <sstream>
#include <tuple>

#include "dataset_parts.h"
#include "s4d/data/npy.h"
#include "s4d/data/poses_bounds.h"
#include "s4d/data/video_reader.h"

namespace s4d::data {
namespace {

namespace fs = std::filesystem;
using detail::fail;

// Same tolerance as read_nerf_cameras: float32 or rounded decimals pass, real scale or shear does not.
constexpr double kRigidTolerance = 1e-3;

// One camera's frames: a folder of PNGs or a video.
struct CameraSource {
  std::string name;              // "cam03"
  std::vector<fs::path> frames;  // camNN/NNNN.png in order; empty for a video
  fs::path video;                // camNN.mp4 when there is no frame folder
  size_t frame_count = 0;
  fs::path first;                // the file the size comes from (first frame or the video)
  int width = 0, height = 0;     // full-resolution frame size
};

std::vector<fs::path> png_files(const fs::path& dir) {
  std::vector<fs::path> files;
  if (!fs::is_directory(dir)) return files;
  for (const auto& entry : fs::directory_iterator(dir)) {
    if (entry.is_regular_file() && entry.path().extension() == ".png") files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

CameraSource folder_camera(const fs::path& root, const std::string& name) {
  CameraSource camera{name, png_files(root / name), {}, 0, {}, 0, 0};
  if (camera.frames.empty()) camera.frames = png_files(root / name / "images");
  if (camera.frames.empty()) fail(root / name, "no .png frames (looked in " + name + "/ and " + name + "/images/)");
  camera.frame_count = camera.frames.size();
  camera.first = camera.frames[0];
  std::tie(camera.width, camera.height) = detail::png_size(camera.first);
  return camera;
}

CameraSource video_camera(const fs::path& root, const std::string& name) {
  const fs::path video = root / (name + ".mp4");
  const VideoInfo info = probe_video(video);
  return {name, {}, video, static_cast<size_t>(info.frames), video, info.width, info.height};
}

std::vector<CameraSource> find_cameras(const fs::path& root) {
  const std::regex cam_name("cam[0-9]+");
  std::vector<std::string> folders, videos;
  for (const auto& entry : fs::directory_iterator(root)) {
    const std::string name = entry.path().filename().string();
    if (entry.is_directory() && std::regex_match(name, cam_name)) folders.push_back(name);
    if (entry.is_regular_file() && entry.path().extension() == ".mp4" && std::regex_match(entry.path().stem().string(), cam_name)) {
      videos.push_back(entry.path().stem().string());
    }
  }
  std::vector<std::string> names = folders;
  for (const std::string& v : videos) {
    if (std::find(folders.begin(), folders.end(), v) == folders.end()) names.push_back(v);
  }
  std::sort(names.begin(), names.end());
  std::vector<CameraSource> cameras;
  for (const std::string& name : names) {
    const bool folder = std::find(folders.begin(), folders.end(), name) != folders.end();
    cameras.push_back(folder ? folder_camera(root, name) : video_camera(root, name));
  }
  if (cameras.empty()) fail(root, "no cameras (camNN/ frame folders or camNN.mp4 videos) next to poses_bounds.npy");
  for (const CameraSource& c : cameras) {
    if (c.frame_count != cameras[0].frame_count) {
      // Frame folders name the files one has and the other lacks; a video has only its count.
      if (c.video.empty() && cameras[0].video.empty())
        fail(root / c.name, detail::frame_count_mismatch(c.frames, cameras[0].name, cameras[0].frames));
      fail(c.video.empty() ? root / c.name : c.video,
           "has " + std::to_string(c.frame_count) + " frames but " + cameras[0].name + " has " +
               std::to_string(cameras[0].frame_count) + "; every camera needs the same frame count");
    }
  }
  return cameras;
}

// The camera of one poses_bounds row, before downscaling. `field` names the row in errors.
io::CameraView llff_camera(const fs::path& npy, const double* row, const std::string& field) {
  for (size_t k = 0; k < kPosesBoundsRow; ++k) {
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

// "0012": a video's frames get the names of frame-folder files as `style4d synth` writes them.
std::string frame_stem(size_t frame) {
  char buf[24];
  std::snprintf(buf, sizeof buf, "%04zu", frame);
  return buf;
}

// "dynerf-frames", "dynerf-4dgaussians" (frames in camNN/images/) or "dynerf-video", after the first camera.
std::string layout_name(const CameraSource& camera) {
  if (camera.frames.empty()) return "dynerf-video";
  return camera.frames[0].parent_path().filename() == "images" ? "dynerf-4dgaussians" : "dynerf-frames";
}

}  // namespace

Dataset load_dynerf(const fs::path& root, const LoadOptions& options) {
  const int factor = detail::checked_downscale(root, options);
  const fs::path npy = root / "poses_bounds.npy";
  if (!fs::exists(npy)) fail(npy, "missing (a DyNeRF / Neu3D dataset needs it)");
  const NpyArray poses = read_npy(npy);
  if (poses.shape.size() != 2 || poses.shape[1] != kPosesBoundsRow) fail(npy, "shape must be (N, 17)");
  const std::vector<CameraSource> cameras = find_cameras(root);
  if (poses.shape[0] != cameras.size()) {
    fail(npy, "shape has " + std::to_string(poses.shape[0]) + " rows but there are " + std::to_string(cameras.size()) +
                  " cameras (" + cameras.front().name + " ... " + cameras.back().name + ")");
  }

  Dataset dataset;
  dataset.kind = "dynerf";
  dataset.layout = layout_name(cameras[0]);
  dataset.root = root;
  const size_t frame_count = cameras[0].frame_count;
  for (size_t c = 0; c < cameras.size(); ++c) {
    const CameraSource& source = cameras[c];
    const std::string field = "row " + std::to_string(c) + " (" + source.name + ")";
    io::CameraView camera = llff_camera(npy, &poses.values[c * kPosesBoundsRow], field);
    // hwf must describe the frames on disk; compare after downscaling, allowing for rounding.
    const int w = source.width, h = source.height;
    const double hwf_w = poses.values[c * kPosesBoundsRow + kPosesBoundsWidth];
    const double hwf_h = poses.values[c * kPosesBoundsRow + kPosesBoundsHeight];
    if (std::abs(detail::downscaled(w, factor) - hwf_w / factor) > 1 ||
        std::abs(detail::downscaled(h, factor) - hwf_h / factor) > 1) {
      fail(npy, field + ": hwf says " + num(hwf_w) + "x" + num(hwf_h) + " (W x H) but " + source.first.string() +
                    " is " + std::to_string(w) + "x" + std::to_string(h));
    }
    camera.width = w;
    camera.height = h;
    detail::downscale_camera(camera, factor);
    for (size_t f = 0; f < frame_count; ++f) {
      const bool video = source.frames.empty();
      detail::add_rig_view(dataset, camera, static_cast<int>(c), source.name,
                           video ? frame_stem(f) : source.frames[f].stem().string(), video ? source.video : source.frames[f],
                           video ? static_cast<int>(f) : -1, f, frame_count);
    }
  }
  detail::finish_dataset(dataset, options, {0.0f, 0.0f, 0.0f}, {"points3D.ply", "points3D_downsample2.ply"});
  return dataset;
}

}  // namespace s4d::data
