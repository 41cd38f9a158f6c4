// `style4d study plan`: a user study from Style4D-Bench outputs. Every bench report (run mode: the
// test cameras' and the spiral's renders, Part 1 "4D stylization"; frames mode: restyled videos,
// Part 2 "video stylization") gives, per scene, style and view, one video per method; each two
// methods of one scene, style and view make a pair. docs/study.md.
#pragma once
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "s4d/study/study_file.h"

namespace s4d::study {

struct PlanOptions {
  std::vector<std::filesystem::path> reports;  // bench output folders (each holds report.json) or report.json files
  std::filesystem::path out;                   // the study folder to create
  int participants = 20;
  uint64_t seed = 1;
  double fps = 30;
  int max_frames = 300;  // the paper's videos: about 10 s, 300 frames
  // Single-frame pairs per part, pulled out of the part's video pairs (the paper: 4 in Part 1, 6 in Part 2).
  int frame_pairs_4d = 4, frame_pairs_video = 6;
  std::vector<std::string> methods;  // only these methods (empty: every method but "original")
};

// The report.json files under a sweep folder's bench/ (one per bench cell), sorted.
std::vector<std::filesystem::path> sweep_reports(const std::filesystem::path& sweep_dir);

// Writes OUT/study.json and OUT/media/ (WebM videos, PNG frames, the style images, the attention
// checks). Throws std::invalid_argument for bad options and a folder that already holds a study,
// std::runtime_error naming the report and field for unreadable inputs.
Study plan_study(const PlanOptions& options);

}  // namespace s4d::study
