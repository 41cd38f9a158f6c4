// The dataset check behind `style4d check-data` and the first step of `style4d train`: a summary of
// a loaded dataset (layout, cameras, frames, resolution, times, bounds, point cloud) and EVERY problem
// found, each naming the file and the field at fault. The loaders already refuse what makes a
// dataset unreadable (and throw at the first such problem); this check looks at what they let
// through: image files missing or of the wrong size, poses that do not face the scene, times out of
// order, repeated or outside [0, 1], non-finite cameras, no test views.
#pragma once
#include <array>
#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "s4d/data/dataset.h"
#include "s4d/util/vec3.h"

namespace s4d::data {

enum class Severity { error, warning };

struct Problem {
  std::filesystem::path file;  // the image, or the dataset file the value came from (poses_bounds.npy, transforms_*.json)
  std::string field;           // "size", "frames[3].time", "row 2 (cam02)", ...
  std::string message;
  Severity severity = Severity::error;
};

struct Resolution {  // one image size after downscale and how many views have it
  int width = 0, height = 0;
  size_t views = 0;
};

struct DatasetSummary {
  std::string layout;  // Dataset::layout, or the kind when the loader names no layout
  std::string kind;
  std::filesystem::path root;
  size_t cameras = 0;  // distinct camera_index; one per view where camera_index is -1
  size_t train_views = 0, test_views = 0;
  size_t min_frames_per_camera = 0, max_frames_per_camera = 0;
  int downscale = 1;
  std::vector<Resolution> resolutions;  // after downscale, most common first
  double time_min = 0, time_max = 0;
  size_t train_times = 0;         // distinct times among the train views
  double train_views_per_time = 0;  // train views / train_times: 1 for a monocular sequence
  bool monocular = false;           // every train time has exactly one train view
  Vec3 centre_min{}, centre_max{};  // camera centres, all views
  double extent = 0;                                 // Dataset::extent
  std::array<float, 3> background{};
  std::string background_source;      // Dataset::background_source
  std::filesystem::path points_file;  // empty: no point cloud
  size_t points = 0;
  std::array<float, 3> points_min{}, points_max{};
  // The point the facing check aims at: the point cloud's centroid, else the point nearest to every
  // camera's optical axis; unset when neither exists (one camera direction and no point cloud).
  std::optional<Vec3> scene_centre;
  std::string scene_centre_from;  // "point cloud centroid" or "nearest point to the optical axes"
  std::vector<std::string> notes;  // what was not checked, and why
};

struct DatasetReport {
  DatasetSummary summary;
  std::vector<Problem> problems;  // in the order found: images, then cameras and poses, then times
  size_t errors() const;
  size_t warnings() const;
};

// Runs every check on a loaded dataset, reading only image headers (PNG IHDR, JPEG SOF) and, for
// videos, the container's frame count and size. Never throws for a problem in the data: each one is
// collected into the report.
DatasetReport check_dataset(const Dataset& dataset);

// What `style4d check-data` and `style4d train` run: loads `root` as load_dataset(root, options) does,
// then checks it. The loader's background probe decodes a few training frames and throws at the first
// bad one; when only the probe fails, the dataset is loaded again without it (the summary notes
// that), the check runs, and the probe's failure is one more error unless the check already names
// that file. Any other load failure is thrown as the loader threw it (the dataset cannot be loaded).
struct CheckedDataset {
  Dataset dataset;
  DatasetReport report;
};
CheckedDataset load_and_check(const std::filesystem::path& root, const LoadOptions& options = {});

// "error: FILE: field: message" (or "warning: ...").
std::string format_problem(const Problem& problem);

// The summary as a short human table, one fact per line, ending with a newline.
std::string format_summary(const DatasetSummary& summary);

// The whole report as JSON text (summary fields, "problems": [{file, field, message, severity}],
// "errors", "warnings").
std::string to_json(const DatasetReport& report);

}  // namespace s4d::data
