// check_dataset: every problem of a loaded dataset, each named by file and field. Where a value came
// from is rebuilt from the layout: DyNeRF cameras are poses_bounds.npy rows (camera_index = row),
// D-NeRF views are the frames of transforms_train.json, transforms_val.json (when present) and
// transforms_test.json in that order, as load_dnerf appends them; HyperNeRF views are camera/ID.json
// with times from metadata.json; COLMAP cameras are sparse/0/images.*; anything else names the image.
#include "s4d/data/dataset_check.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <exception>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "dataset_parts.h"
#include "video_reader.h"

namespace s4d::data {
namespace {

namespace fs = std::filesystem;
using Vec3 = std::array<double, 3>;

// Shortest form of a number for messages ("2704", "0.333333").
std::string num(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

std::string size_text(int w, int h) { return std::to_string(w) + "x" + std::to_string(h); }

std::string vec_text(const Vec3& v) { return "(" + num(v[0]) + ", " + num(v[1]) + ", " + num(v[2]) + ")"; }

// Where one view's values came from: the file, and the field names in it.
struct ViewSource {
  fs::path file;         // the camera's file (poses_bounds.npy, transforms_*.json; else the image)
  std::string pose;      // field of the pose
  std::string intrinsics;
  fs::path time_file;    // the time's file (DyNeRF: the frame, whose order gives the time)
  std::string time;
  std::string image;     // field naming the image file in `file`; empty when the image is found by listing
  bool sequence = false;  // `time_file` lists a monocular sequence whose frames should go forward in time
};

// D-NeRF: (transforms file, frame index) of every view, in load_dnerf's order; empty when the files
// do not account for the views exactly (a dataset built in memory, or changed since it was loaded).
std::vector<std::pair<fs::path, size_t>> dnerf_frames(const Dataset& dataset) {
  std::vector<std::pair<fs::path, size_t>> out;
  for (const char* name : {"transforms_train.json", "transforms_val.json", "transforms_test.json"}) {
    const fs::path path = dataset.root / name;
    if (!fs::exists(path)) continue;
    std::ifstream in(path);
    const nlohmann::json j = nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/false);
    if (!j.is_object() || !j.contains("frames") || !j["frames"].is_array()) return {};
    for (size_t i = 0; i < j["frames"].size(); ++i) out.emplace_back(path, i);
  }
  if (out.size() != dataset.views.size()) return {};
  return out;
}

std::vector<ViewSource> view_sources(const Dataset& dataset) {
  std::vector<ViewSource> sources;
  const auto dnerf = dataset.kind == "dnerf" ? dnerf_frames(dataset) : std::vector<std::pair<fs::path, size_t>>{};
  for (size_t k = 0; k < dataset.views.size(); ++k) {
    const View& v = dataset.views[k];
    ViewSource s;
    if (dataset.kind == "dynerf" && v.camera_index >= 0) {
      const std::string camera = v.name.substr(0, v.name.find('/'));
      s.file = dataset.root / "poses_bounds.npy";
      s.pose = "row " + std::to_string(v.camera_index) + " (" + camera + ")";
      s.intrinsics = s.pose + " hwf";
      s.time_file = v.image;
      s.time = v.frame_in_file >= 0 ? "frame " + std::to_string(v.frame_in_file) + " time" : "time (from the frame order)";
    } else if (dataset.kind == "colmap" && v.camera_index >= 0) {
      const std::string camera = v.name.substr(0, v.name.find('/'));
      const fs::path sparse = dataset.root / "sparse" / "0";
      s.file = fs::exists(sparse / "images.bin") ? sparse / "images.bin" : sparse / "images.txt";
      s.pose = "image " + camera + " (qvec, tvec)";
      s.intrinsics = "image " + camera + " (its camera's intrinsics)";
      s.time_file = v.image;
      s.time = "time (from the frame order)";
    } else if (dataset.kind == "hypernerf") {
      s.file = dataset.root / "camera" / (v.name + ".json");
      s.pose = "orientation, position";
      s.intrinsics = "focal_length, principal_point, image_size";
      s.time_file = dataset.root / "metadata.json";
      s.time = v.name + ".warp_id";
    } else if (!dnerf.empty()) {
      const std::string frame = "frames[" + std::to_string(dnerf[k].second) + "]";
      s.file = s.time_file = dnerf[k].first;
      s.pose = frame + ".transform_matrix";
      s.intrinsics = frame + " intrinsics";
      s.time = frame + ".time";
      s.image = frame + ".file_path";
      s.sequence = true;
    } else {
      s.file = s.time_file = v.image;
      s.pose = "pose (view " + v.name + ")";
      s.intrinsics = "intrinsics (view " + v.name + ")";
      s.time = "time (view " + v.name + ")";
    }
    sources.push_back(std::move(s));
  }
  return sources;
}

// Collects problems, dropping exact repeats (views of one DyNeRF camera share its pose row).
class Problems {
 public:
  void add(const fs::path& file, const std::string& field, const std::string& message, Severity severity) {
    Problem p{file, field, message, severity};
    if (seen_.insert(format_problem(p)).second) list_.push_back(std::move(p));
  }
  void error(const fs::path& file, const std::string& field, const std::string& message) {
    add(file, field, message, Severity::error);
  }
  void warning(const fs::path& file, const std::string& field, const std::string& message) {
    add(file, field, message, Severity::warning);
  }
  std::vector<Problem> take() { return std::move(list_); }

 private:
  std::set<std::string> seen_;
  std::vector<Problem> list_;
};

// (width, height) from a baseline or progressive JPEG's SOFn segment, without decoding the image.
std::pair<int, int> jpeg_size(const fs::path& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) detail::fail(path, "cannot open");
  auto byte = [&]() {
    const int c = f.get();
    if (c == std::char_traits<char>::eof()) detail::fail(path, "not a JPEG file (no frame header before the end)");
    return c;
  };
  if (byte() != 0xFF || byte() != 0xD8) detail::fail(path, "not a JPEG file");
  for (;;) {
    int marker = byte();
    if (marker != 0xFF) detail::fail(path, "not a JPEG file (bad marker)");
    while (marker == 0xFF) marker = byte();  // fill bytes
    if (marker == 0xD8 || marker == 0x01 || (marker >= 0xD0 && marker <= 0xD7)) continue;  // no length
    const int length = byte() << 8 | byte();
    if (length < 2) detail::fail(path, "not a JPEG file (bad segment length)");
    const bool sof = marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 && marker != 0xC8 && marker != 0xCC;
    if (sof) {
      byte();  // sample precision
      const int height = byte() << 8 | byte();
      const int width = byte() << 8 | byte();
      if (width <= 0 || height <= 0) detail::fail(path, "bad JPEG size in the frame header");
      return {width, height};
    }
    f.seekg(length - 2, std::ios::cur);
  }
}

// The image file's size from its header; nullopt for a format whose header is not read.
std::optional<std::pair<int, int>> header_size(const fs::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext == ".png") return detail::png_size(path);
  if (ext == ".jpg" || ext == ".jpeg") return jpeg_size(path);
  return std::nullopt;
}

Vec3 camera_centre(const io::CameraView& c) {
  const auto& m = c.world_to_cam;
  Vec3 o{};
  for (size_t i = 0; i < 3; ++i) o[i] = -(m[i] * m[3] + m[4 + i] * m[7] + m[8 + i] * m[11]);
  return o;
}

Vec3 to_camera(const io::CameraView& c, const Vec3& p) {
  Vec3 x{};
  for (size_t i = 0; i < 3; ++i) {
    x[i] = c.world_to_cam[i * 4] * p[0] + c.world_to_cam[i * 4 + 1] * p[1] + c.world_to_cam[i * 4 + 2] * p[2] +
           c.world_to_cam[i * 4 + 3];
  }
  return x;
}

// The point nearest (least squares) to the optical axes of `cameras`: solves
// sum (I - d d^T) p = sum (I - d d^T) c. nullopt when the axes are (nearly) parallel.
std::optional<Vec3> nearest_to_axes(const std::vector<const io::CameraView*>& cameras) {
  double a[3][3] = {};
  Vec3 b{};
  for (const io::CameraView* cam : cameras) {
    const Vec3 c = camera_centre(*cam);
    Vec3 d{cam->world_to_cam[8], cam->world_to_cam[9], cam->world_to_cam[10]};  // forward (third row of R)
    const double n = std::hypot(d[0], d[1], d[2]);
    if (!(n > 0)) continue;
    for (double& x : d) x /= n;
    for (size_t i = 0; i < 3; ++i) {
      for (size_t j = 0; j < 3; ++j) {
        const double m = (i == j ? 1.0 : 0.0) - d[i] * d[j];
        a[i][j] += m;
        b[i] += m * c[j];
      }
    }
  }
  auto det3 = [](const double m[3][3]) {
    return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
           m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
  };
  const double det = det3(a);
  const double scale = (a[0][0] + a[1][1] + a[2][2]) / 3;
  if (!(scale > 0) || !(std::abs(det) > 1e-6 * scale * scale * scale)) return std::nullopt;
  Vec3 p{};
  for (size_t k = 0; k < 3; ++k) {  // Cramer's rule
    double m[3][3];
    for (size_t i = 0; i < 3; ++i) {
      for (size_t j = 0; j < 3; ++j) m[i][j] = j == k ? b[i] : a[i][j];
    }
    p[k] = det3(m) / det;
  }
  return p;
}

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

void check_images(const Dataset& dataset, const std::vector<ViewSource>& sources, Problems& problems,
                  DatasetSummary& summary) {
  struct VideoProbe {
    bool probed = false, size_checked = false;
    std::optional<detail::VideoInfo> info;  // unset when the video cannot be opened
  };
  std::map<fs::path, VideoProbe> videos;
  std::map<std::string, size_t> unread;  // extension -> images whose size was not read
  for (size_t k = 0; k < dataset.views.size(); ++k) {
    const View& v = dataset.views[k];
    const ViewSource& s = sources[k];
    const bool video = v.frame_in_file >= 0;
    const int ds = v.file_downscale > 0 ? v.file_downscale : std::max(1, dataset.downscale);
    if (!fs::exists(v.image)) {
      if (!s.image.empty()) problems.error(s.file, s.image, "image " + v.image.string() + " does not exist");
      else problems.error(v.image, "file", std::string(video ? "video" : "image") + " does not exist (view " + v.name + ")");
      continue;
    }
    std::optional<std::pair<int, int>> size;
    if (video) {
      VideoProbe& probe = videos[v.image];
      if (!probe.probed) {
        probe.probed = true;
        try {
          probe.info = detail::probe_video(v.image);
        } catch (const std::exception& e) {
          problems.error(v.image, "file", e.what());
        }
      }
      if (!probe.info) continue;
      if (v.frame_in_file >= probe.info->frames) {
        problems.error(v.image, "frame " + std::to_string(v.frame_in_file),
                       "view " + v.name + " reads frame " + std::to_string(v.frame_in_file) + " but the video has " +
                           std::to_string(probe.info->frames) + " frames");
      }
      if (probe.size_checked) continue;
      probe.size_checked = true;
      size = std::pair{probe.info->width, probe.info->height};
    } else {
      try {
        size = header_size(v.image);
      } catch (const std::exception& e) {
        // png_size / jpeg_size say "<path>: <what>"; keep the what.
        std::string what = e.what();
        const std::string prefix = v.image.string() + ": ";
        if (what.rfind(prefix, 0) == 0) what = what.substr(prefix.size());
        problems.error(v.image, "file", what);
        continue;
      }
      if (!size) {
        ++unread[v.image.extension().string()];
        continue;
      }
    }
    const int w = size->first, h = size->second;
    const int cw = v.camera.width, ch = v.camera.height;
    if (w / ds != cw || h / ds != ch) {
      std::string expected = size_text(cw, ch);
      if (ds > 1) {
        expected += " at downscale " + std::to_string(ds) + ", which needs " + std::to_string(cw * ds) + ".." +
                    std::to_string(cw * ds + ds - 1) + " x " + std::to_string(ch * ds) + ".." +
                    std::to_string(ch * ds + ds - 1);
      }
      problems.error(v.image, "size",
                     "is " + size_text(w, h) + " but the view's camera (" + s.file.filename().string() + " " + s.pose +
                         ") is " + expected);
    }
  }
  for (const auto& [ext, count] : unread) {
    summary.notes.push_back("sizes of " + std::to_string(count) + " " + (ext.empty() ? "extension-less" : ext) +
                            " images not checked (only PNG and JPEG headers are read)");
  }
}

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
    if (const std::optional<Vec3> p = nearest_to_axes(cams)) {
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

void fill_summary(const Dataset& dataset, DatasetSummary& s) {
  s.layout = dataset.layout.empty() ? dataset.kind : dataset.layout;
  s.kind = dataset.kind;
  s.root = dataset.root;
  s.downscale = dataset.downscale;
  s.extent = dataset.extent;
  s.background = dataset.background;
  s.background_source = dataset.background_source;
  std::map<int, size_t> frames;  // camera_index -> views
  size_t own_cameras = 0;
  std::map<std::pair<int, int>, size_t> sizes;
  std::map<double, size_t> train_times;
  bool first = true;
  for (const View& v : dataset.views) {
    if (v.camera_index >= 0) ++frames[v.camera_index];
    else ++own_cameras;
    (v.test ? s.test_views : s.train_views) += 1;
    ++sizes[{v.camera.width, v.camera.height}];
    if (!v.test) ++train_times[v.time];
    const Vec3 c = camera_centre(v.camera);
    if (first) {
      s.time_min = s.time_max = v.time;
      s.centre_min = s.centre_max = c;
      first = false;
    }
    s.time_min = std::min(s.time_min, v.time);
    s.time_max = std::max(s.time_max, v.time);
    for (size_t a = 0; a < 3; ++a) {
      s.centre_min[a] = std::min(s.centre_min[a], c[a]);
      s.centre_max[a] = std::max(s.centre_max[a], c[a]);
    }
  }
  s.cameras = frames.size() + own_cameras;
  if (!frames.empty()) {
    s.min_frames_per_camera = s.max_frames_per_camera = frames.begin()->second;
    for (const auto& [c, n] : frames) {
      s.min_frames_per_camera = std::min(s.min_frames_per_camera, n);
      s.max_frames_per_camera = std::max(s.max_frames_per_camera, n);
    }
  }
  if (own_cameras > 0) {
    s.min_frames_per_camera = frames.empty() ? 1 : std::min<size_t>(s.min_frames_per_camera, 1);
    s.max_frames_per_camera = std::max<size_t>(s.max_frames_per_camera, 1);
  }
  for (const auto& [wh, n] : sizes) s.resolutions.push_back({wh.first, wh.second, n});
  std::stable_sort(s.resolutions.begin(), s.resolutions.end(),
                   [](const Resolution& a, const Resolution& b) { return a.views > b.views; });
  s.train_times = train_times.size();
  s.train_views_per_time = train_times.empty() ? 0 : static_cast<double>(s.train_views) / static_cast<double>(train_times.size());
  s.monocular = !train_times.empty() &&
                std::all_of(train_times.begin(), train_times.end(), [](const auto& t) { return t.second == 1; });
  s.points_file = dataset.points_file;
  s.points = dataset.points.size() / 3;
  for (size_t i = 0; i < s.points; ++i) {
    for (size_t a = 0; a < 3; ++a) {
      const float x = dataset.points[i * 3 + a];
      s.points_min[a] = i == 0 ? x : std::min(s.points_min[a], x);
      s.points_max[a] = i == 0 ? x : std::max(s.points_max[a], x);
    }
  }
}

const char* severity_name(Severity s) { return s == Severity::error ? "error" : "warning"; }

}  // namespace

size_t DatasetReport::errors() const {
  return static_cast<size_t>(
      std::count_if(problems.begin(), problems.end(), [](const Problem& p) { return p.severity == Severity::error; }));
}

size_t DatasetReport::warnings() const { return problems.size() - errors(); }

DatasetReport check_dataset(const Dataset& dataset) {
  DatasetReport report;
  fill_summary(dataset, report.summary);
  const std::vector<ViewSource> sources = view_sources(dataset);
  Problems problems;
  check_images(dataset, sources, problems, report.summary);
  check_cameras(dataset, sources, problems, report.summary);
  check_times(dataset, sources, problems);
  if (report.summary.test_views == 0) {
    problems.warning(dataset.root, "split", "no test views: training will report no test PSNR or SSIM");
  }
  if (!dataset.background_conflict.empty()) problems.warning(dataset.root, "background", dataset.background_conflict);
  if (!dataset.points_file.empty() && dataset.points.empty()) {
    problems.warning(dataset.points_file, "points", "the point cloud is empty; training starts from random points");
  }
  report.problems = problems.take();
  return report;
}

CheckedDataset load_and_check(const fs::path& root, const LoadOptions& options) {
  CheckedDataset out;
  std::exception_ptr first;
  std::string what;
  try {
    out.dataset = load_dataset(root, options);
  } catch (const std::exception& e) {
    if (!options.probe_background) throw;
    first = std::current_exception();
    what = e.what();
  }
  if (!first) {
    out.report = check_dataset(out.dataset);
    return out;
  }
  LoadOptions without = options;
  without.probe_background = false;
  try {
    out.dataset = load_dataset(root, without);
  } catch (const std::exception&) {
    std::rethrow_exception(first);  // not (only) the probe: the loader's own message
  }
  out.report = check_dataset(out.dataset);
  out.report.summary.notes.push_back("background not probed from the frames: decoding them failed (see the errors)");
  // The probe's message is "<file>: <what>": name the view's file when it is one.
  fs::path file = root;
  std::string message = what;
  for (const View& v : out.dataset.views) {
    const std::string prefix = v.image.string() + ": ";
    if (what.rfind(prefix, 0) == 0) {
      file = v.image;
      message = what.substr(prefix.size());
      break;
    }
  }
  const bool named = std::any_of(out.report.problems.begin(), out.report.problems.end(), [&](const Problem& p) {
    return p.severity == Severity::error && file != root &&
           (p.file == file || p.message.find(file.string()) != std::string::npos);
  });
  if (!named) {
    out.report.problems.push_back(
        {file, "pixels", "cannot be decoded (the background probe read it): " + message, Severity::error});
  }
  return out;
}

std::string format_problem(const Problem& p) {
  return std::string(severity_name(p.severity)) + ": " + p.file.string() + ": " + p.field + ": " + p.message;
}

std::string format_summary(const DatasetSummary& s) {
  std::ostringstream o;
  auto row = [&](const char* name) -> std::ostringstream& {
    const std::string n = name;
    o << n << std::string(n.size() < 15 ? 15 - n.size() : 1, ' ');
    return o;
  };
  auto range = [](double a, double b) { return a == b ? num(a) : num(a) + " .. " + num(b); };
  row("dataset") << s.root.string() << "\n";
  row("layout") << s.layout << (s.layout != s.kind ? " (" + s.kind + ")" : "") << "\n";
  row("cameras") << s.cameras << ", "
                 << (s.min_frames_per_camera == s.max_frames_per_camera
                         ? std::to_string(s.min_frames_per_camera)
                         : std::to_string(s.min_frames_per_camera) + " to " + std::to_string(s.max_frames_per_camera))
                 << (s.max_frames_per_camera == 1 ? " frame" : " frames") << " per camera\n";
  row("views") << s.train_views << " train, " << s.test_views << " test\n";
  std::string res;
  for (const Resolution& r : s.resolutions) {
    res += (res.empty() ? "" : ", ") + size_text(r.width, r.height) + (s.resolutions.size() > 1 ? " (" + std::to_string(r.views) + " views)" : "");
  }
  row("resolution") << res << " after downscale " << s.downscale << "\n";
  row("time") << range(s.time_min, s.time_max) << "; " << s.train_times << " train times, " << num(s.train_views_per_time)
              << (s.train_views_per_time == 1 ? " train view" : " train views") << " per time ("
              << (s.monocular ? "monocular" : "multi-view") << ")\n";
  row("camera centres") << "x " << range(s.centre_min[0], s.centre_max[0]) << ", y " << range(s.centre_min[1], s.centre_max[1])
                        << ", z " << range(s.centre_min[2], s.centre_max[2]) << "; extent " << num(s.extent) << "\n";
  row("background") << num(s.background[0]) << ", " << num(s.background[1]) << ", " << num(s.background[2])
                    << (s.background_source.empty() ? "" : " (" + s.background_source + ")") << "\n";
  if (s.points_file.empty()) {
    row("point cloud") << "none (training starts from random points)\n";
  } else {
    row("point cloud") << s.points_file.string() << ": " << s.points << " points";
    if (s.points > 0) {
      o << ", x " << range(s.points_min[0], s.points_max[0]) << ", y " << range(s.points_min[1], s.points_max[1]) << ", z "
        << range(s.points_min[2], s.points_max[2]);
    }
    o << "\n";
  }
  if (s.scene_centre) row("scene centre") << vec_text(*s.scene_centre) << ", " << s.scene_centre_from << "\n";
  for (const std::string& note : s.notes) row("note") << note << "\n";
  return o.str();
}

std::string to_json(const DatasetReport& report) {
  const DatasetSummary& s = report.summary;
  nlohmann::json resolutions = nlohmann::json::array();
  for (const Resolution& r : s.resolutions) resolutions.push_back({{"width", r.width}, {"height", r.height}, {"views", r.views}});
  nlohmann::json summary = {
      {"root", s.root.string()},
      {"layout", s.layout},
      {"kind", s.kind},
      {"cameras", s.cameras},
      {"train_views", s.train_views},
      {"test_views", s.test_views},
      {"frames_per_camera", {{"min", s.min_frames_per_camera}, {"max", s.max_frames_per_camera}}},
      {"downscale", s.downscale},
      {"resolutions", resolutions},
      {"time_range", {s.time_min, s.time_max}},
      {"train_times", s.train_times},
      {"train_views_per_time", s.train_views_per_time},
      {"monocular", s.monocular},
      {"camera_centres", {{"min", s.centre_min}, {"max", s.centre_max}}},
      {"extent", s.extent},
      {"background", s.background},
      {"background_source", s.background_source},
      {"notes", s.notes},
  };
  if (s.points_file.empty()) {
    summary["point_cloud"] = nullptr;
  } else {
    summary["point_cloud"] = {{"file", s.points_file.string()}, {"points", s.points}};
    if (s.points > 0) summary["point_cloud"]["bounds"] = {{"min", s.points_min}, {"max", s.points_max}};
  }
  if (s.scene_centre) summary["scene_centre"] = {{"point", *s.scene_centre}, {"from", s.scene_centre_from}};
  else summary["scene_centre"] = nullptr;
  nlohmann::json problems = nlohmann::json::array();
  for (const Problem& p : report.problems) {
    problems.push_back(
        {{"file", p.file.string()}, {"field", p.field}, {"message", p.message}, {"severity", severity_name(p.severity)}});
  }
  return nlohmann::json{{"summary", summary}, {"problems", problems}, {"errors", report.errors()}, {"warnings", report.warnings()}}
             .dump(2) +
         "\n";
}

}  // namespace s4d::data
