// check_dataset: every problem of a loaded dataset, each named by file and field. Where a value came
// from is rebuilt from the layout: DyNeRF cameras are poses_bounds.npy rows (camera_index = row),
// D-NeRF views are the frames of transforms_train.json, transforms_val.json (when present) and
// transforms_test.json in that order, as load_dnerf appends them; HyperNeRF views are camera/ID.json
// with times from metadata.json; COLMAP cameras are sparse/0/images.*; anything else names the image.
#include "s4d/data/dataset_check.h"

#include <algorithm>
#include <exception>
#include <fstream>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <utility>

#include "dataset_check_parts.h"

namespace s4d::data {
namespace {

namespace fs = std::filesystem;
using detail::Problems;
using detail::ViewSource;
using detail::check_cameras;
using detail::check_frame_content;
using detail::check_images;
using detail::check_times;
using detail::fill_summary;

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
  check_frame_content(dataset, problems);
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

}  // namespace s4d::data
