// HyperNeRF / Nerfies layout, read as google/hypernerf (datasets/nerfies.py, interp.py, camera.py) and
// 4DGaussians (scene/hyper_loader.py, dataset_readers.py) read it:
//   dataset.json    {count, num_exemplars, ids, train_ids, val_ids}; ids in capture order
//   metadata.json   {ID: {warp_id, appearance_id, camera_id, time_id?}}
//   scene.json      {scale, center, near, far}
//   camera/ID.json  orientation (3x3 whose rows are the camera's axes in world: a world-to-camera
//                   rotation), position (the camera centre in world), focal_length, principal_point
//                   [cx, cy], skew, pixel_aspect_ratio, radial_distortion [k1, k2, k3],
//                   tangential_distortion [p1, p2], image_size [w, h]
//   rgb/1x/ID.png   the full-resolution frame
//   points3D_downsample2.ply (4DGaussians' COLMAP cloud) or points.npy (HyperNeRF's): initial points
// Axes: HyperNeRF projects p to local = orientation (p - position), then pixel (f x/z + skew y/z + cx,
// f aspect y/z + cy) with pixel centres at +0.5: our OpenCV convention as is, fy = f * aspect.
// Scene normalisation (HyperNeRF's load_camera and load_points): centre -> (position - center) * scale,
// points likewise. points3D_downsample2.ply needs it too: 4DGaussians' hypernerf2colmap.py poses COLMAP
// with the raw json positions, so its cloud is in the raw world frame.
// Time: warp_id / max warp_id over all ids, as 4DGaussians (HyperNeRF itself maps time to [-1, 1]).
// Splits: train_ids and val_ids (the test views). The "interp" captures have no val_ids; there both
// 4DGaussians and HyperNeRF's InterpDataSource (interval 4) train on every 4th id and test on the
// middle one between consecutive training ids, so ids at odd positions are not loaded at all.
// Resolution: --downscale N reads HyperNeRF's own rgb/Nx/ when it holds the frame (its size is the 1x
// size divided by N and rounded, as HyperNeRF's camera.scale; intrinsics divide by N), else box-filters
// rgb/1x/ like the other layouts.
// Distortion: 4DGaussians ignores it, and published captures carry a little (the Nerfies README's
// example camera moves the corner by ~0.6 % of the diagonal), so small distortion is ignored too; more than
// kMaxIgnoredDistortion is refused rather than silently mis-modelled. Skew must be 0.
// camera_index stays -1 even for the two-camera "vrig" captures: the rig is handheld, so no view
// shares its pose with another, which is what camera_index >= 0 means to the protocols and viewer.
// Background: white, 4DGaussians' default (white_background, not overridden for HyperNeRF); frames
// are opaque, so it only colours what the Gaussians leave uncovered.
#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "dataset_parts.h"
#include "s4d/util/vec3.h"

namespace s4d::data {
namespace {

namespace fs = std::filesystem;
using detail::fail;
using nlohmann::json;

// Same tolerance as read_nerf_cameras and the DyNeRF loader: float32 or rounded decimals pass.
constexpr double kRigidTolerance = 1e-3;
// Largest pixel displacement distortion may cause at the image border, as a share of the image
// diagonal, for it to be ignored.
constexpr double kMaxIgnoredDistortion = 0.02;
// The interp captures' split: 4DGaussians' fixed stride (HyperNeRF's InterpDataSource.interval).
constexpr size_t kInterpInterval = 4;

std::string num(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

json read_json(const fs::path& path) {
  if (!fs::is_regular_file(path)) fail(path, "missing (a HyperNeRF dataset needs it)");
  std::ifstream in(path);
  try {
    return json::parse(in);
  } catch (const json::exception& e) {
    fail(path, std::string("not valid JSON: ") + e.what());
  }
}

const json& member(const fs::path& path, const json& object, const std::string& prefix, const char* key) {
  if (!object.is_object() || !object.contains(key)) fail(path, prefix + key + ": missing");
  return object[key];
}

double finite_number(const fs::path& path, const json& value, const std::string& field) {
  if (!value.is_number()) fail(path, field + ": must be a number");
  const double v = value.get<double>();
  if (!std::isfinite(v)) fail(path, field + ": must be finite");
  return v;
}

// A numeric array of exactly `n` finite entries.
std::vector<double> numbers(const fs::path& path, const json& value, const std::string& field, size_t n) {
  if (!value.is_array() || value.size() != n) fail(path, field + ": must be an array of " + std::to_string(n) + " numbers");
  std::vector<double> out;
  for (size_t i = 0; i < n; ++i) out.push_back(finite_number(path, value[i], field + "[" + std::to_string(i) + "]"));
  return out;
}

// An id as HyperNeRF takes it (str() of a string or an integer); it names files, so it must stay a
// plain file name inside camera/ and rgb/1x/.
std::string item_id(const fs::path& path, const json& value, const std::string& field) {
  std::string id;
  if (value.is_string()) id = value.get<std::string>();
  else if (value.is_number_integer()) id = std::to_string(value.get<long long>());
  else fail(path, field + ": must be a string or an integer");
  if (id.empty() || id == "." || id == ".." || id.find_first_of("/\\") != std::string::npos)
    fail(path, field + ": '" + id + "' is not a plain file name");
  return id;
}

std::vector<std::string> id_list(const fs::path& path, const json& object, const char* key) {
  const json& list = member(path, object, "", key);
  if (!list.is_array()) fail(path, std::string(key) + ": must be an array of ids");
  std::vector<std::string> ids;
  for (size_t i = 0; i < list.size(); ++i) ids.push_back(item_id(path, list[i], std::string(key) + "[" + std::to_string(i) + "]"));
  return ids;
}

struct SceneNormalisation {
  Vec3 center{};
  double scale = 1;
  Vec3 apply(const Vec3& p) const {
    return {(p[0] - center[0]) * scale, (p[1] - center[1]) * scale, (p[2] - center[2]) * scale};
  }
};

SceneNormalisation read_scene(const fs::path& path) {
  const json j = read_json(path);
  SceneNormalisation n;
  n.scale = finite_number(path, member(path, j, "", "scale"), "scale");
  if (!(n.scale > 0)) fail(path, "scale: must be > 0, got " + num(n.scale));
  const std::vector<double> c = numbers(path, member(path, j, "", "center"), "center", 3);
  std::copy(c.begin(), c.end(), n.center.begin());
  return n;
}

// How far (pixels) the distortion moves the image's corners and edge midpoints: HyperNeRF's
// camera.project polynomial applied to the undistorted ray through each.
double distortion_pixels(const io::CameraView& c, const std::vector<double>& k, const std::vector<double>& p) {
  double worst = 0;
  for (double u : {0.0, 0.5, 1.0}) {
    for (double v : {0.0, 0.5, 1.0}) {
      const double x = (u * c.width - c.cx) / c.fx, y = (v * c.height - c.cy) / c.fy;
      const double r2 = x * x + y * y;
      const double d = 1 + r2 * (k[0] + r2 * (k[1] + k[2] * r2));
      const double xd = x * d + 2 * p[0] * x * y + p[1] * (r2 + 2 * x * x);
      const double yd = y * d + 2 * p[1] * x * y + p[0] * (r2 + 2 * y * y);
      worst = std::max(worst, std::hypot((xd - x) * c.fx, (yd - y) * c.fy));
    }
  }
  return worst;
}

// The camera of camera/ID.json at full resolution, in the normalised scene.
io::CameraView read_camera(const fs::path& path, const SceneNormalisation& scene) {
  const json j = read_json(path);
  const json& rows = member(path, j, "", "orientation");
  if (!rows.is_array() || rows.size() != 3) fail(path, "orientation: must be 3 rows of 3 numbers");
  double r[3][3];
  for (size_t i = 0; i < 3; ++i) {
    const std::vector<double> row = numbers(path, rows[i], "orientation[" + std::to_string(i) + "]", 3);
    std::copy(row.begin(), row.end(), r[i]);
  }
  double worst = 0;
  for (int a = 0; a < 3; ++a) {
    for (int b = 0; b < 3; ++b) {
      const double dot = r[a][0] * r[b][0] + r[a][1] * r[b][1] + r[a][2] * r[b][2];
      worst = std::max(worst, std::abs(dot - (a == b ? 1.0 : 0.0)));
    }
  }
  const double det = r[0][0] * (r[1][1] * r[2][2] - r[1][2] * r[2][1]) - r[0][1] * (r[1][0] * r[2][2] - r[1][2] * r[2][0]) +
                     r[0][2] * (r[1][0] * r[2][1] - r[1][1] * r[2][0]);
  if (worst > kRigidTolerance || std::abs(det - 1.0) > kRigidTolerance)
    fail(path, "orientation: not a rotation (rows must be orthonormal with determinant +1, within 1e-3)");
  const std::vector<double> position = numbers(path, member(path, j, "", "position"), "position", 3);
  const Vec3 centre = scene.apply({position[0], position[1], position[2]});

  io::CameraView camera;
  // world_to_cam = [R | -R c] with R = orientation and c the normalised centre.
  for (size_t i = 0; i < 3; ++i) {
    double t = 0;
    for (size_t k = 0; k < 3; ++k) {
      camera.world_to_cam[i * 4 + k] = r[i][k];
      t -= r[i][k] * centre[k];
    }
    camera.world_to_cam[i * 4 + 3] = t;
  }
  camera.world_to_cam[15] = 1;

  const double focal = finite_number(path, member(path, j, "", "focal_length"), "focal_length");
  if (!(focal > 0)) fail(path, "focal_length: must be > 0, got " + num(focal));
  const double aspect = j.contains("pixel_aspect_ratio") ? finite_number(path, j["pixel_aspect_ratio"], "pixel_aspect_ratio") : 1.0;
  if (!(aspect > 0)) fail(path, "pixel_aspect_ratio: must be > 0, got " + num(aspect));
  const std::vector<double> pp = numbers(path, member(path, j, "", "principal_point"), "principal_point", 2);
  const std::vector<double> size = numbers(path, member(path, j, "", "image_size"), "image_size", 2);
  if (size[0] < 1 || size[1] < 1 || size[0] != std::floor(size[0]) || size[1] != std::floor(size[1]) || size[0] > 1 << 24 ||
      size[1] > 1 << 24)
    fail(path, "image_size: must be two positive integers [width, height]");
  camera.fx = focal;
  camera.fy = focal * aspect;
  camera.cx = pp[0];
  camera.cy = pp[1];
  camera.width = static_cast<int>(size[0]);
  camera.height = static_cast<int>(size[1]);

  // Skew would shear the image; no 3DGS rasteriser models it, and HyperNeRF's own captures have none.
  const double skew = j.contains("skew") ? finite_number(path, j["skew"], "skew") : 0.0;
  if (std::abs(skew) > 1e-9 * focal) fail(path, "skew: must be 0 (skewed pixels are not modelled), got " + num(skew));
  // Old Nerfies files call tangential_distortion "tangential" (HyperNeRF's Camera.from_json).
  const char* tangential_key = j.contains("tangential_distortion") ? "tangential_distortion" : "tangential";
  const std::vector<double> k =
      j.contains("radial_distortion") ? numbers(path, j["radial_distortion"], "radial_distortion", 3) : std::vector<double>(3, 0.0);
  const std::vector<double> p =
      j.contains(tangential_key) ? numbers(path, j[tangential_key], tangential_key, 2) : std::vector<double>(2, 0.0);
  const double moved = distortion_pixels(camera, k, p), diagonal = std::hypot(camera.width, camera.height);
  if (moved > kMaxIgnoredDistortion * diagonal) {
    fail(path, "radial_distortion / tangential_distortion: move the image border by " + num(std::round(moved)) +
                   " px, more than " + num(kMaxIgnoredDistortion * 100) +
                   " % of the diagonal; HyperNeRF distortion is not modelled (undistort the images first)");
  }
  return camera;
}

// Which ids are loaded, and whether each is a test view, in the order of `ids`.
std::vector<std::pair<size_t, bool>> choose_split(const fs::path& path, const json& j, const std::vector<std::string>& ids) {
  const std::vector<std::string> val = id_list(path, j, "val_ids");
  std::vector<std::pair<size_t, bool>> chosen;
  if (val.empty()) {
    // Interp captures: train on ids 0, 4, 8, ..., last; test on 2, 6, ..., the middles between them.
    const size_t last_train = (ids.size() - 1) / kInterpInterval * kInterpInterval;
    for (size_t i = 0; i <= last_train; i += kInterpInterval / 2) chosen.emplace_back(i, i % kInterpInterval != 0);
    return chosen;
  }
  const std::vector<std::string> train = id_list(path, j, "train_ids");
  std::map<std::string, size_t> position;
  for (size_t i = 0; i < ids.size(); ++i) position[ids[i]] = i;
  std::map<size_t, bool> test_of;
  for (const auto& [list, key, test] : {std::tuple{&train, "train_ids", false}, std::tuple{&val, "val_ids", true}}) {
    for (size_t k = 0; k < list->size(); ++k) {
      const std::string field = std::string(key) + "[" + std::to_string(k) + "]";
      const auto at = position.find((*list)[k]);
      if (at == position.end()) fail(path, field + ": '" + (*list)[k] + "' is not in ids");
      if (!test_of.emplace(at->second, test).second) fail(path, field + ": '" + (*list)[k] + "' is listed twice in train_ids / val_ids");
    }
  }
  // Ids in neither list are not loaded, as in HyperNeRF and 4DGaussians.
  for (const auto& [index, test] : test_of) chosen.emplace_back(index, test);
  return chosen;
}

}  // namespace

Dataset load_hypernerf(const fs::path& root, const LoadOptions& options) {
  const int factor = detail::checked_downscale(root, options);
  const fs::path dataset_json = root / "dataset.json", metadata_json = root / "metadata.json";
  const json dj = read_json(dataset_json);
  const std::vector<std::string> ids = id_list(dataset_json, dj, "ids");
  if (ids.empty()) fail(dataset_json, "ids: empty");
  if (dj.contains("count") && !(dj["count"].is_number_integer() && dj["count"].get<long long>() == static_cast<long long>(ids.size())))
    fail(dataset_json, "count: must equal the number of ids (" + std::to_string(ids.size()) + ")");
  std::set<std::string> seen;
  for (size_t i = 0; i < ids.size(); ++i) {
    if (!seen.insert(ids[i]).second) fail(dataset_json, "ids[" + std::to_string(i) + "]: '" + ids[i] + "' appears twice");
  }
  const std::vector<std::pair<size_t, bool>> chosen = choose_split(dataset_json, dj, ids);
  const SceneNormalisation scene = read_scene(root / "scene.json");

  // Times: warp_id over the largest one among all ids (4DGaussians); a single warp id is time 0.
  const json meta = read_json(metadata_json);
  std::vector<long long> warp(ids.size());
  long long max_warp = 0;
  for (size_t i = 0; i < ids.size(); ++i) {
    const json& entry = member(metadata_json, meta, "", ids[i].c_str());
    const json& w = member(metadata_json, entry, ids[i] + ".", "warp_id");
    if (!w.is_number_integer() || w.get<long long>() < 0) fail(metadata_json, ids[i] + ".warp_id: must be an integer >= 0");
    warp[i] = w.get<long long>();
    max_warp = std::max(max_warp, warp[i]);
  }

  Dataset dataset;
  dataset.kind = "hypernerf";
  dataset.layout = "hypernerf";
  dataset.root = root;
  for (const auto& [index, test] : chosen) {
    const std::string& id = ids[index];
    const std::string field = "ids[" + std::to_string(index) + "]";
    const fs::path camera_json = root / "camera" / (id + ".json"), full = root / "rgb" / "1x" / (id + ".png");
    const fs::path scaled = root / "rgb" / (std::to_string(factor) + "x") / (id + ".png");
    const bool prescaled = factor > 1 && fs::is_regular_file(scaled);
    const fs::path image = prescaled ? scaled : full;
    if (!fs::is_regular_file(camera_json)) fail(dataset_json, field + ": '" + id + "' has no camera file " + camera_json.string());
    if (!fs::is_regular_file(image)) {
      fail(dataset_json, field + ": '" + id + "' has no image " + image.string() +
                             (factor > 1 ? " (nor " + scaled.string() + ")" : std::string()));
    }
    View view;
    view.camera = read_camera(camera_json, scene);
    const auto [w, h] = detail::png_size(image);
    const int want_w = prescaled ? static_cast<int>(std::lround(double(view.camera.width) / factor)) : view.camera.width;
    const int want_h = prescaled ? static_cast<int>(std::lround(double(view.camera.height) / factor)) : view.camera.height;
    if (w != want_w || h != want_h) {
      fail(camera_json, "image_size: says " + std::to_string(view.camera.width) + "x" + std::to_string(view.camera.height) +
                            (prescaled ? " (" + std::to_string(want_w) + "x" + std::to_string(want_h) + " at " +
                                             std::to_string(factor) + "x)" : std::string()) +
                            " but " + image.string() + " is " + std::to_string(w) + "x" + std::to_string(h));
    }
    detail::downscale_camera(view.camera, factor);
    if (prescaled) {
      view.camera.width = w, view.camera.height = h;
      view.file_downscale = 1;
    }
    view.name = id;
    view.image = image;
    view.time = max_warp > 0 ? static_cast<double>(warp[index]) / static_cast<double>(max_warp) : 0.0;
    view.test = test;
    view.camera.name = id;
    view.camera.file_path = fs::relative(image, root).generic_string();
    view.camera.time = view.time;
    dataset.views.push_back(std::move(view));
  }
  detail::finish_dataset(dataset, options, {1.0f, 1.0f, 1.0f}, {"points3D_downsample2.ply", "points.npy"});
  for (size_t i = 0; i + 2 < dataset.points.size(); i += 3) {
    const Vec3 p = scene.apply({dataset.points[i], dataset.points[i + 1], dataset.points[i + 2]});
    for (size_t k = 0; k < 3; ++k) dataset.points[i + k] = static_cast<float>(p[k]);
  }
  return dataset;
}

}  // namespace s4d::data
