// check_cameras and check_times: every view's pose and intrinsics are usable and its camera faces
// the scene; times lie in [0, 1] and go forward with each camera's frames.
#include <cmath>
#include <map>
#include <optional>
#include <set>

#include "dataset_check_parts.h"
#include "s4d/data/camera_geometry.h"

namespace s4d::data::detail {

namespace {

// Views that stand for distinct cameras: the first of each camera_index, and every view without one.
std::vector<size_t> camera_representatives(const Dataset& dataset) {
  std::vector<size_t> out;
  std::set<int> seen;
  for (size_t k = 0; k < dataset.views.size(); ++k) {
    const int c = dataset.views[k].camera_index;
    if (c < 0 || seen.insert(c).second) out.push_back(k);
  }
  return out;
}

}  // namespace

void check_cameras(const Dataset& dataset, const std::vector<ViewSource>& sources, Problems& problems,
                   DatasetSummary& summary) {
  // Every view's values (views of one camera repeat its problems, which Problems drops); the facing
  // check then takes one view per camera among those whose values are usable.
  std::vector<bool> usable(dataset.views.size(), true);
  for (size_t k = 0; k < dataset.views.size(); ++k) {
    const View& v = dataset.views[k];
    const ViewSource& s = sources[k];
    bool ok = true;
    for (double x : v.camera.world_to_cam) ok = ok && std::isfinite(x);
    if (!ok) problems.error(s.file, s.pose, "non-finite value in the pose");
    if (!std::isfinite(v.camera.fx) || !std::isfinite(v.camera.fy) || !std::isfinite(v.camera.cx) ||
        !std::isfinite(v.camera.cy)) {
      problems.error(s.file, s.intrinsics, "non-finite focal length or principal point");
      ok = false;
    } else if (!(v.camera.fx > 0 && v.camera.fy > 0)) {
      problems.error(s.file, s.intrinsics, "focal length must be positive, got fx " + num(v.camera.fx) + ", fy " + num(v.camera.fy));
      ok = false;
    }
    if (v.camera.width <= 0 || v.camera.height <= 0) {
      problems.error(s.file, s.intrinsics, "image size " + size_text(v.camera.width, v.camera.height) +
                                               " after downscale " + std::to_string(dataset.downscale) + " is empty");
      ok = false;
    }
    usable[k] = ok;
  }
  std::vector<size_t> finite;
  for (size_t k : camera_representatives(dataset)) {
    if (usable[k]) finite.push_back(k);
  }

  // The scene centre the cameras should face.
  if (!dataset.points.empty()) {
    Vec3 c{};
    const size_t n = dataset.points.size() / 3;
    for (size_t i = 0; i < n; ++i) {
      for (size_t a = 0; a < 3; ++a) c[a] += static_cast<double>(dataset.points[i * 3 + a]) / static_cast<double>(n);
    }
    if (std::isfinite(c[0]) && std::isfinite(c[1]) && std::isfinite(c[2])) {
      summary.scene_centre = c;
      summary.scene_centre_from = "point cloud centroid";
    }
  }
  if (!summary.scene_centre) {
    std::vector<const io::CameraView*> cams;
    for (size_t k : finite) cams.push_back(&dataset.views[k].camera);
    if (const std::optional<Vec3> p = nearest_to_optical_axes(cams)) {
      summary.scene_centre = *p;
      summary.scene_centre_from = "nearest point to the optical axes";
    } else {
      summary.notes.push_back("facing not checked: no point cloud, and the cameras' optical axes are parallel");
    }
  }
  if (!summary.scene_centre) return;
  const Vec3 p = *summary.scene_centre;
  const std::string what = "the scene centre " + vec_text(p) + " (" + summary.scene_centre_from + ")";
  for (size_t k : finite) {
    const View& v = dataset.views[k];
    const ViewSource& s = sources[k];
    const Vec3 x = to_camera(v.camera, p);
    if (!(x[2] > 0)) {
      problems.error(s.file, s.pose,
                     "camera faces away from the scene: " + what + " is behind it (z = " + num(x[2]) +
                         " in camera coordinates)");
      continue;
    }
    const double u = v.camera.fx * x[0] / x[2] + v.camera.cx, py = v.camera.fy * x[1] / x[2] + v.camera.cy;
    if (!(u >= 0 && u <= v.camera.width && py >= 0 && py <= v.camera.height)) {
      problems.warning(s.file, s.pose,
                       "camera does not see the scene centre: " + what + " projects to pixel (" + num(u) + ", " + num(py) +
                           "), outside the " + size_text(v.camera.width, v.camera.height) + " image");
    }
  }
}

void check_times(const Dataset& dataset, const std::vector<ViewSource>& sources, Problems& problems) {
  for (size_t k = 0; k < dataset.views.size(); ++k) {
    const double t = dataset.views[k].time;
    if (!std::isfinite(t) || t < 0 || t > 1) {
      problems.error(sources[k].time_file, sources[k].time, "time " + num(t) + " is outside [0, 1]");
    }
  }
  // Physical cameras: times increase with frame order, and no time twice.
  std::map<int, std::vector<size_t>> by_camera;
  for (size_t k = 0; k < dataset.views.size(); ++k) {
    if (dataset.views[k].camera_index >= 0) by_camera[dataset.views[k].camera_index].push_back(k);
  }
  for (const auto& [camera, views] : by_camera) {
    std::map<double, size_t> seen;
    for (size_t n = 0; n < views.size(); ++n) {
      const View& v = dataset.views[views[n]];
      const ViewSource& s = sources[views[n]];
      if (!std::isfinite(v.time)) continue;
      const auto [at, fresh] = seen.emplace(v.time, views[n]);
      if (!fresh) {
        problems.error(s.time_file, s.time,
                       "duplicate (camera " + std::to_string(camera) + ", time " + num(v.time) + "): view " + v.name +
                           " has the time of view " + dataset.views[at->second].name);
      } else if (n > 0 && v.time < dataset.views[views[n - 1]].time) {
        const View& prev = dataset.views[views[n - 1]];
        problems.error(s.time_file, s.time,
                       "times out of order: view " + v.name + " has time " + num(v.time) + " after view " + prev.name +
                           " at " + num(prev.time) + " (camera " + std::to_string(camera) + "'s frames must go forward in time)");
      }
    }
  }
  // Monocular files (D-NeRF's transforms_*.json): the frames are listed in time order in the datasets
  // we know; a time going back is suspicious but does not stop training.
  std::map<fs::path, std::vector<size_t>> by_file;
  for (size_t k = 0; k < dataset.views.size(); ++k) {
    if (dataset.views[k].camera_index < 0 && sources[k].sequence) by_file[sources[k].time_file].push_back(k);
  }
  for (const auto& [file, views] : by_file) {
    for (size_t n = 1; n < views.size(); ++n) {
      const View& v = dataset.views[views[n]];
      const View& prev = dataset.views[views[n - 1]];
      if (v.time < prev.time) {
        problems.warning(file, sources[views[n]].time,
                         "times out of order: " + num(v.time) + " after " + num(prev.time) + " (" + sources[views[n - 1]].time +
                             "); the frames of a monocular sequence are expected in time order");
      }
    }
  }
}

}  // namespace s4d::data::detail
