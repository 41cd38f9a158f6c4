// Private to s4d_data: what the parts of check_dataset share (dataset_check.cpp: where each view's
// values came from and the checks' order; dataset_check_images.cpp, dataset_check_poses.cpp,
// dataset_check_frames.cpp: the checks; dataset_check_summary.cpp: the summary and its text and JSON
// forms).
#pragma once

#include <array>
#include <filesystem>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "s4d/data/dataset.h"
#include "s4d/data/dataset_check.h"
#include "s4d/util/vec3.h"

namespace s4d::data::detail {

namespace fs = std::filesystem;

// Shortest form of a number for messages ("2704", "0.333333").
inline std::string num(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

inline std::string size_text(int w, int h) { return std::to_string(w) + "x" + std::to_string(h); }

// "(x, y, z)"; appended, as a literal + std::string trips GCC 12's false -Wrestrict here.
inline std::string vec_text(const Vec3& v) {
  std::string s = "(";
  s += num(v[0]) + ", " + num(v[1]) + ", " + num(v[2]) + ")";
  return s;
}

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


void check_images(const Dataset& dataset, const std::vector<ViewSource>& sources, Problems& problems,
                  DatasetSummary& summary);
void check_cameras(const Dataset& dataset, const std::vector<ViewSource>& sources, Problems& problems,
                   DatasetSummary& summary);
void check_times(const Dataset& dataset, const std::vector<ViewSource>& sources, Problems& problems);
void check_frame_content(const Dataset& dataset, Problems& problems);
void fill_summary(const Dataset& dataset, DatasetSummary& s);

}  // namespace s4d::data::detail
