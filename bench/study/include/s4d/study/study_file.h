// A user study as data: STUDY/study.json, which `style4d study plan` writes and `serve` and
// `report` read. Its pairs (items), the criteria each kind of item is judged on, and each
// participant's seeded order and left/right placement. docs/study.md describes the format.
#pragma once
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace s4d::study {

inline constexpr const char* kFormat = "style4d-study/1";

struct Criterion {
  std::string id;        // "stylization", "consistency", "video_quality", "image_quality"
  std::string question;  // what the page asks
};

// The paper's criteria: videos on stylization, spatiotemporal consistency and video quality;
// single frames on stylization and image quality.
const std::vector<Criterion>& video_criteria();
const std::vector<Criterion>& frame_criteria();

struct Part {
  std::string id;     // "4d" (Part 1: 4D stylization) or "video" (Part 2: video stylization)
  std::string title;
};

// One pair shown side by side. methods[k] is shown from media[k]; a participant's `swap` puts
// media[1] on the left.
struct Item {
  std::string id;
  std::string part;
  std::string kind;  // "video" or "frame"
  std::string scene, style, view;  // view: "test/cam00", "spiral" or "frames"
  std::string methods[2];
  std::string media[2];     // paths relative to the study folder
  std::string style_image;  // relative path, or empty when the bench recorded none
  // "" for a real pair; "identical" (the same video twice: the answer is "same") or "broken" (one
  // side visibly corrupted: the answer is the other side, `intact`).
  std::string check;
  int intact = 0;
  const std::vector<Criterion>& criteria() const { return kind == "video" ? video_criteria() : frame_criteria(); }
};

struct Placement {
  std::string item;
  bool swap = false;  // true: media[1] on the left
};

struct Participant {
  std::string code;
  std::vector<Placement> order;
};

struct Study {
  std::filesystem::path root;  // the study folder
  uint64_t seed = 0;
  double fps = 30;
  std::vector<Part> parts;
  std::vector<Item> items;
  std::vector<Participant> participants;

  // Throw std::invalid_argument naming study.json and the id when absent.
  const Item& item(const std::string& id) const;
  const Participant* participant(const std::string& code) const;  // nullptr when unknown
};

nlohmann::json to_json(const Study& s);
// Throws std::runtime_error naming STUDY/study.json and the field on anything malformed.
Study read_study(const std::filesystem::path& study_dir);
void write_study(const Study& s);  // STUDY/study.json, atomically

}  // namespace s4d::study
