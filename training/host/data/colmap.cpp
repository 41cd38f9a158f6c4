// COLMAP multi-camera-rig layout ("colmap-multiview"): what a user gets by running COLMAP on the
// first frame of each camera of their own rig.
//   sparse/0/cameras, images, points3D   COLMAP's model, .bin preferred over .txt (colmap_model.h)
//   CAM/NNNN.png or CAM/images/NNNN.png  frames of the rig camera whose COLMAP image is named
//                                        "CAM.png", "CAM/0000.png" or "CAM/images/0000.png": the first
//                                        path component, extension removed
// Each COLMAP image is one physical camera; its pose holds for every frame of that camera (a static
// rig). qvec / tvec are COLMAP's world-to-camera rotation and translation in OpenCV axes (x right,
// y down, z forward), which is our world_to_cam as it stands: no axis flips, no recentring.
// Intrinsics come from the image's COLMAP camera, scaled to the frames' size when COLMAP ran at
// another resolution; only pinhole models (or others with all distortion exactly 0) are accepted,
// since the renderer has no distortion. The first camera by name is the held-out test camera (the
// Neu3D protocol); time = frame / (T - 1).
#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

#include "colmap_model.h"
#include "dataset_parts.h"

namespace s4d::data {
namespace {

namespace fs = std::filesystem;
using detail::fail;

// Shortest form of a number for messages ("2704", "12.5").
std::string num(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

// sparse/0/<stem>.bin, else .txt.
fs::path model_file(const fs::path& sparse, const std::string& stem) {
  const fs::path bin = sparse / (stem + ".bin"), txt = sparse / (stem + ".txt");
  if (fs::is_regular_file(bin)) return bin;
  if (fs::is_regular_file(txt)) return txt;
  fail(bin, "missing, and so is " + txt.filename().string() + " (a COLMAP model needs cameras, images and points3D)");
}

// "image 3 'cam02.png'": how errors name an image.
std::string image_label(const colmap::Image& image) { return "image " + std::to_string(image.id) + " '" + image.name + "'"; }

// One rig camera: its COLMAP image and frames.
struct RigCamera {
  std::string name;  // frame folder, "cam02"
  const colmap::Image* image = nullptr;
  std::vector<fs::path> frames;  // sorted
};

// The frame folder an image name maps to: its first path component without extension.
std::string folder_of(const fs::path& images_file, const colmap::Image& image) {
  const std::string first = image.name.substr(0, image.name.find_first_of("/\\"));
  const std::string folder = fs::path(first).stem().string();
  if (folder.empty() || folder == "." || folder == "..") {
    fail(images_file, image_label(image) + ": name: no camera folder in it (expected 'cam00.png' or 'cam00/0000.png')");
  }
  return folder;
}

std::vector<fs::path> find_frames(const fs::path& root, const fs::path& images_file, const RigCamera& camera) {
  fs::path dir = root / camera.name;
  if (!fs::is_directory(dir)) {
    fail(dir, "missing: the frame folder of " + image_label(*camera.image) + " in " + images_file.string());
  }
  if (fs::is_directory(dir / "images")) dir /= "images";
  std::vector<fs::path> frames;
  for (const auto& entry : fs::directory_iterator(dir)) {
    if (entry.is_regular_file() && entry.path().extension() == ".png") frames.push_back(entry.path());
  }
  std::sort(frames.begin(), frames.end());
  if (frames.empty()) fail(dir, "no .png frames");
  return frames;
}

// Rig cameras in name order, with their frames; every camera has the same frame count.
std::vector<RigCamera> rig_cameras(const fs::path& root, const fs::path& images_file, const std::vector<colmap::Image>& images) {
  if (images.empty()) fail(images_file, "no images");
  std::map<std::string, const colmap::Image*> by_folder;
  for (const colmap::Image& image : images) {
    const std::string folder = folder_of(images_file, image);
    const auto [it, inserted] = by_folder.emplace(folder, &image);
    if (!inserted) {
      fail(images_file, image_label(image) + ": name: maps to frame folder '" + folder + "' like " +
                            image_label(*it->second) + "; give one image per rig camera");
    }
  }
  std::vector<RigCamera> cameras;
  for (const auto& [folder, image] : by_folder) {
    RigCamera camera{folder, image, {}};
    camera.frames = find_frames(root, images_file, camera);
    cameras.push_back(std::move(camera));
  }
  for (const RigCamera& c : cameras) {
    if (c.frames.size() != cameras[0].frames.size()) {
      fail(c.frames[0].parent_path(), detail::frame_count_mismatch(c.frames, cameras[0].name, cameras[0].frames));
    }
  }
  return cameras;
}

// world_to_cam = [R(q) | t] from the image's normalised quaternion (w, x, y, z).
void set_pose(io::CameraView& camera, const fs::path& images_file, const colmap::Image& image) {
  for (double v : image.q) {
    if (!std::isfinite(v)) fail(images_file, image_label(image) + ": qvec: non-finite value");
  }
  for (double v : image.t) {
    if (!std::isfinite(v)) fail(images_file, image_label(image) + ": tvec: non-finite value");
  }
  const double n = std::sqrt(image.q[0] * image.q[0] + image.q[1] * image.q[1] + image.q[2] * image.q[2] + image.q[3] * image.q[3]);
  if (!(n > 1e-12)) fail(images_file, image_label(image) + ": qvec: zero quaternion");
  const double w = image.q[0] / n, x = image.q[1] / n, y = image.q[2] / n, z = image.q[3] / n;
  const double r[3][3] = {{1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)},
                          {2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)},
                          {2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)}};
  auto& m = camera.world_to_cam;
  m = {};
  for (size_t i = 0; i < 3; ++i) {
    for (size_t j = 0; j < 3; ++j) m[i * 4 + j] = r[i][j];
    m[i * 4 + 3] = image.t[i];
  }
  m[15] = 1;
}

// Pinhole intrinsics of a COLMAP camera, scaled from its WIDTH x HEIGHT to the frames' size.
void set_intrinsics(io::CameraView& camera, const fs::path& cameras_file, const colmap::Camera& c, const fs::path& frame,
                    int width, int height) {
  const colmap::CameraModel& model = *c.model;
  const std::string where = "camera " + std::to_string(c.id) + " (" + model.name + ")";
  if (model.fisheye) {
    fail(cameras_file, where + ": model: fisheye projection; undistort the images first (colmap image_undistorter) "
                               "and use its pinhole sparse model");
  }
  for (double v : c.params) {
    if (!std::isfinite(v)) fail(cameras_file, where + ": params: non-finite value");
  }
  const size_t distortion_at = model.single_focal ? 3 : 4;
  for (size_t k = distortion_at; k < c.params.size(); ++k) {
    if (c.params[k] != 0) {
      fail(cameras_file, where + ": params: distortion parameter " + std::to_string(k - distortion_at + 1) + " is " +
                             num(c.params[k]) + ", not 0; undistort the images first (colmap image_undistorter) "
                             "and use its pinhole sparse model");
    }
  }
  const double fx = c.params[0], fy = c.params[model.single_focal ? 0 : 1];
  const double cx = c.params[distortion_at - 2], cy = c.params[distortion_at - 1];
  if (!(fx > 0 && fy > 0)) fail(cameras_file, where + ": params: focal length must be > 0");
  if (c.width < 1 || c.height < 1) fail(cameras_file, where + ": width and height must be >= 1");

  // COLMAP may have run on images of another size (e.g. full resolution): accept a uniform rescale,
  // allowing one pixel for the rounding of an odd size.
  const double cw = static_cast<double>(c.width), ch = static_cast<double>(c.height);
  const double sx = width / cw, sy = height / ch;
  if (std::abs(ch * sx - height) > 1 || std::abs(cw * sy - width) > 1) {
    fail(cameras_file, where + ": width, height: " + num(cw) + "x" + num(ch) + " is not a uniform rescale of " +
                           frame.string() + " (" + std::to_string(width) + "x" + std::to_string(height) + ")");
  }
  camera.fx = fx * sx;
  camera.fy = fy * sy;
  camera.cx = cx * sx;
  camera.cy = cy * sy;
  camera.width = width;
  camera.height = height;
}

}  // namespace

Dataset load_colmap(const fs::path& root, const LoadOptions& options) {
  const int factor = detail::checked_downscale(root, options);
  const fs::path sparse = root / "sparse" / "0";
  const fs::path cameras_file = model_file(sparse, "cameras"), images_file = model_file(sparse, "images");
  const std::vector<colmap::Camera> colmap_cameras = colmap::read_cameras(cameras_file);
  const std::vector<colmap::Image> images = colmap::read_images(images_file);

  std::map<int, const colmap::Camera*> camera_by_id;
  for (const colmap::Camera& c : colmap_cameras) {
    if (!camera_by_id.emplace(c.id, &c).second) fail(cameras_file, "camera " + std::to_string(c.id) + ": camera_id: duplicate");
  }
  for (const colmap::Image& image : images) {
    if (!camera_by_id.count(image.camera_id)) {
      fail(images_file, image_label(image) + ": camera_id " + std::to_string(image.camera_id) + " is not in " +
                            cameras_file.filename().string());
    }
  }
  const std::vector<RigCamera> rig = rig_cameras(root, images_file, images);

  Dataset dataset;
  dataset.kind = "colmap";
  dataset.layout = "colmap-multiview";
  dataset.root = root;
  const size_t frame_count = rig[0].frames.size();
  for (size_t c = 0; c < rig.size(); ++c) {
    const RigCamera& source = rig[c];
    io::CameraView camera;
    set_pose(camera, images_file, *source.image);
    const auto [width, height] = detail::png_size(source.frames[0]);
    set_intrinsics(camera, cameras_file, *camera_by_id.at(source.image->camera_id), source.frames[0], width, height);
    detail::downscale_camera(camera, factor);
    for (size_t f = 0; f < frame_count; ++f) {
      detail::add_rig_view(dataset, camera, static_cast<int>(c), source.name, source.frames[f].stem().string(),
                           source.frames[f], -1, f, frame_count);
    }
  }
  detail::finish_dataset(dataset, options, {0.0f, 0.0f, 0.0f}, {"sparse/0/points3D.bin", "sparse/0/points3D.txt"});
  return dataset;
}

}  // namespace s4d::data
