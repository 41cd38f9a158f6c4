// The dataset's summary (fill_summary) and the report's text and JSON forms.
#include <algorithm>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "dataset_check_parts.h"
#include "s4d/data/camera_geometry.h"

namespace s4d::data {

namespace detail {

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

}  // namespace detail

namespace {

using detail::num;
using detail::size_text;
using detail::vec_text;

const char* severity_name(Severity s) { return s == Severity::error ? "error" : "warning"; }

}  // namespace

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
