#include "s4d/study/study_plan.h"

#include <algorithm>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <stdexcept>

#include "s4d/data/webm_video.h"
#include "study_media.h"

namespace s4d::study {

namespace {

namespace fs = std::filesystem;

// One method's frames for one scene, style and view.
struct Sequence {
  fs::path frames;
  std::string style_image;  // as the bench recorded it, or empty
};

struct GroupKey {
  std::string part, scene, style, view;
  auto operator<=>(const GroupKey&) const = default;
};

uint64_t splitmix(uint64_t& state) {
  uint64_t z = (state += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

// Fisher-Yates with our own generator, so a seed gives the same study with every standard library.
template <class T>
void shuffle(std::vector<T>& v, uint64_t& state) {
  for (size_t i = v.size(); i > 1; --i) std::swap(v[i - 1], v[splitmix(state) % i]);
}

// Names become file names and URL paths.
std::string safe_name(const std::string& s) {
  std::string out;
  for (char c : s) out += (std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == '.') ? c : '_';
  return out.empty() || out[0] == '.' ? "_" + out : out;
}

nlohmann::json read_json(const fs::path& file) {
  std::ifstream in(file);
  if (!in) throw std::runtime_error(file.string() + ": cannot read");
  std::stringstream text;
  text << in.rdbuf();
  try {
    return nlohmann::json::parse(text.str());
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(file.string() + ": not JSON: " + e.what());
  }
}

std::string text_field(const nlohmann::json& j, const char* name, const fs::path& file, const std::string& where) {
  if (!j.contains(name) || !j.at(name).is_string())
    throw std::runtime_error(file.string() + ": " + where + "." + name + ": missing or not a string");
  return j.at(name).get<std::string>();
}

// A recorded input path: as written (absolute, or relative to where the bench ran), else under the
// report's own folder by the bench's layout (renders/METHOD/PROTOCOL), for a report moved with
// its renders.
fs::path locate(const std::string& recorded, const fs::path& fallback, const fs::path& file, const std::string& where) {
  if (fs::exists(recorded)) return recorded;
  if (!fallback.empty() && fs::exists(fallback)) return fallback;
  throw std::runtime_error(file.string() + ": " + where + ": '" + recorded + "' does not exist" +
                           (fallback.empty() ? "" : " (nor " + fallback.string() + ")"));
}

// The method as the study names it: a sweep's "STYLE.METHOD" names become METHOD, so that one
// method's votes add up over styles.
std::string method_name(const std::string& method, const std::string& style) {
  return method.rfind(style + ".", 0) == 0 ? method.substr(style.size() + 1) : method;
}

void add_report(const fs::path& given, const PlanOptions& o, std::map<GroupKey, std::map<std::string, Sequence>>& groups) {
  if (!fs::exists(given)) throw std::runtime_error(given.string() + ": does not exist (a bench output folder, or its report.json)");
  const fs::path file = fs::is_directory(given) ? given / "report.json" : given;
  const nlohmann::json report = read_json(file);
  if (!report.contains("results") || !report.at("results").is_array())
    throw std::runtime_error(file.string() + ": results: missing (not a Style4D-Bench report.json)");
  for (size_t r = 0; r < report.at("results").size(); ++r) {
    const nlohmann::json& res = report.at("results")[r];
    const std::string where = "results[" + std::to_string(r) + "]";
    const std::string style = text_field(res, "style", file, where), scene = text_field(res, "scene", file, where);
    const std::string raw = text_field(res, "method", file, where), method = method_name(raw, style);
    const bool wanted = o.methods.empty() ? method != "original"
                                          : std::find(o.methods.begin(), o.methods.end(), method) != o.methods.end();
    if (!wanted) continue;
    if (!res.contains("inputs") || !res.at("inputs").is_object())
      throw std::runtime_error(file.string() + ": " + where + ".inputs: missing");
    const nlohmann::json& in = res.at("inputs");
    const std::string style_image = in.contains("style_image") && in.at("style_image").is_string() ? in.at("style_image").get<std::string>() : "";
    const fs::path renders = file.parent_path() / "renders" / raw;
    auto add = [&](const std::string& part, const std::string& view, const fs::path& frames) {
      Sequence& s = groups[{part, scene, style, view}][method];
      if (!s.frames.empty())
        throw std::runtime_error(file.string() + ": " + where + ": method '" + method + "' of scene '" + scene + "', style '" +
                                 style + "', view '" + view + "' is also in an earlier report (" + s.frames.string() + ")");
      s = {frames, style_image};
    };
    if (in.contains("test")) {  // run mode: each test camera's fixed-view video, and the spiral
      const fs::path test = locate(text_field(in, "test", file, where + ".inputs"), renders / "test", file, where + ".inputs.test");
      std::vector<fs::path> cams;
      for (const auto& e : fs::directory_iterator(test))
        if (e.is_directory()) cams.push_back(e.path());
      std::sort(cams.begin(), cams.end());
      for (const fs::path& cam : cams) add("4d", "test/" + cam.filename().string(), cam);
      add("4d", "spiral", locate(text_field(in, "spiral", file, where + ".inputs"), renders / "spiral", file, where + ".inputs.spiral"));
    } else {  // frames mode: one restyled video per method
      add("video", "frames", locate(text_field(in, "frames", file, where + ".inputs"), {}, file, where + ".inputs.frames"));
    }
  }
}

std::string participant_code(uint64_t& state) {
  static const char kAlphabet[] = "ABCDEFGHJKLMNPQRSTUVWXYZ23456789";  // no 0/O, 1/I
  std::string code;
  for (int k = 0; k < 8; ++k) code += kAlphabet[splitmix(state) % 32];
  return code;
}

}  // namespace

std::vector<fs::path> sweep_reports(const fs::path& sweep_dir) {
  const fs::path bench = sweep_dir / "bench";
  if (!fs::is_directory(bench))
    throw std::invalid_argument("--sweep: " + bench.string() + " is missing (no bench cell has run; `style4d sweep status`)");
  std::vector<fs::path> out;
  for (const auto& e : fs::recursive_directory_iterator(bench))
    if (e.is_regular_file() && e.path().filename() == "report.json") out.push_back(e.path());
  std::sort(out.begin(), out.end());
  if (out.empty()) throw std::invalid_argument("--sweep: no report.json under " + bench.string() + " (no bench cell has finished)");
  return out;
}

Study plan_study(const PlanOptions& o) {
  if (o.reports.empty()) throw std::invalid_argument("study plan: give bench outputs with --bench DIR or --sweep SWEEP");
  if (o.participants < 1 || o.participants > 100000) throw std::invalid_argument("--participants: expected 1 to 100000");
  if (!(o.fps > 0 && o.fps <= 240)) throw std::invalid_argument("--fps: expected a number in (0, 240]");
  if (o.max_frames < 2) throw std::invalid_argument("--max-frames: expected at least 2");
  if (o.frame_pairs_4d < 0 || o.frame_pairs_video < 0) throw std::invalid_argument("--frame-pairs: expected a non-negative count");
  if (fs::exists(o.out / "study.json"))
    throw std::invalid_argument((o.out / "study.json").string() +
                                ": the folder already holds a study (its votes belong to that plan); plan into a new --out");
  std::map<GroupKey, std::map<std::string, Sequence>> groups;
  for (const fs::path& r : o.reports) add_report(r, o, groups);

  Study s;
  s.root = o.out;
  s.seed = o.seed;
  s.fps = o.fps;
  std::map<std::string, std::vector<size_t>> video_pairs;  // part -> indices into s.items
  std::map<fs::path, std::map<int, fs::path>> stills;      // frames -> index -> PNG to write
  std::map<fs::path, fs::path> videos;                     // frames -> WebM to write
  std::map<std::string, std::string> style_images;         // style -> media path
  int next_id = 0;
  auto new_id = [&](char kind) {
    char buf[16];
    std::snprintf(buf, sizeof buf, "%c%03d", kind, ++next_id);
    return std::string(buf);
  };
  for (const auto& [key, methods] : groups) {
    if (methods.size() < 2) continue;
    const fs::path dir = fs::path("media") / key.part / safe_name(key.scene) / safe_name(key.style) / safe_name(key.view);
    std::string style_media;
    const std::string& recorded = methods.begin()->second.style_image;
    if (!recorded.empty() && fs::exists(recorded)) {
      style_media = (fs::path("media") / "styles" / (safe_name(key.style) + fs::path(recorded).extension().string())).string();
      style_images[style_media] = recorded;
    }
    for (auto a = methods.begin(); a != methods.end(); ++a)
      for (auto b = std::next(a); b != methods.end(); ++b) {
        Item it{new_id('v'), key.part, "video", key.scene, key.style, key.view, {a->first, b->first},
                {(dir / (safe_name(a->first) + ".webm")).string(), (dir / (safe_name(b->first) + ".webm")).string()},
                style_media, "", 0};
        videos[a->second.frames] = it.media[0];
        videos[b->second.frames] = it.media[1];
        video_pairs[key.part].push_back(s.items.size());
        s.items.push_back(it);
      }
  }
  if (s.items.empty())
    throw std::invalid_argument("study plan: no scene, style and view has two methods to compare (bench two or more styles or "
                                "methods of one run, e.g. `style4d bench --run RUN --style A --style B`)");
  auto frames_of = [&](const std::string& media) {
    for (const auto& [frames, webm] : videos)
      if (webm == media) return frames;
    throw std::logic_error("no frames for " + media);
  };

  // Single frames, as the paper pulls them out of its video pairs: the part's video pairs taken in
  // turn, each at evenly spaced times (the middle of equal stretches of its length).
  for (const char* part : {"4d", "video"}) {
    const int want = std::string(part) == "4d" ? o.frame_pairs_4d : o.frame_pairs_video;
    const std::vector<size_t>& pairs = video_pairs[part];
    if (pairs.empty()) continue;
    s.parts.push_back({part, std::string(part) == "4d" ? "Part 1: 4D stylization" : "Part 2: video stylization"});
    for (int f = 0; f < want; ++f) {
      const Item v = s.items[pairs[f % pairs.size()]];
      const int picks = want / static_cast<int>(pairs.size()) + (static_cast<int>(f % pairs.size()) < want % static_cast<int>(pairs.size()) ? 1 : 0);
      const int j = f / static_cast<int>(pairs.size());
      const int n = std::min(data::webm_frame_count(frames_of(v.media[0]), o.max_frames), data::webm_frame_count(frames_of(v.media[1]), o.max_frames));
      const int index = static_cast<int>((j + 0.5) * n / picks);
      Item it = v;
      it.id = new_id('f');
      it.kind = "frame";
      char suffix[32];
      std::snprintf(suffix, sizeof suffix, "_f%04d.png", index);
      for (int k = 0; k < 2; ++k) {
        it.media[k] = (fs::path(v.media[k]).parent_path() / (fs::path(v.media[k]).stem().string() + suffix)).string();
        stills[frames_of(v.media[k])][index] = it.media[k];
      }
      s.items.push_back(it);
    }
  }

  // Attention checks on the first part's first video pair: the same video on both sides, and the
  // video against a visibly broken copy of itself.
  const Item first = s.items[video_pairs[s.parts.front().id].front()];
  Item same = first;
  same.id = "c001";
  same.methods[1] = first.methods[0];
  same.media[1] = first.media[0];
  same.check = "identical";
  Item broken = first;
  broken.id = "c002";
  broken.methods[1] = first.methods[0] + " (broken)";
  broken.media[1] = "media/checks/broken.webm";
  broken.check = "broken";
  broken.intact = 0;
  s.items.push_back(same);
  s.items.push_back(broken);

  // Each participant: parts in order, within a part the videos then the frames, each shuffled,
  // and every pair's sides drawn.
  uint64_t state = o.seed;
  std::set<std::string> codes;
  for (int p = 0; p < o.participants; ++p) {
    Participant person;
    do person.code = participant_code(state);
    while (!codes.insert(person.code).second);
    for (const Part& part : s.parts)
      for (const char* kind : {"video", "frame"}) {
        std::vector<Placement> block;
        for (const Item& it : s.items)
          if (it.part == part.id && it.kind == kind) block.push_back({it.id, false});
        shuffle(block, state);
        for (Placement& b : block) b.swap = (splitmix(state) & 1) != 0;
        person.order.insert(person.order.end(), block.begin(), block.end());
      }
    s.participants.push_back(std::move(person));
  }

  fs::create_directories(o.out);
  for (const auto& [frames, webm] : videos) {
    const std::map<int, fs::path>& picks = stills[frames];
    data::encode_webm(frames, o.max_frames, o.fps, o.out / webm, [&](int index, const io::ImageF& frame) {
      if (auto it = picks.find(index); it != picks.end()) {
        fs::create_directories((o.out / it->second).parent_path());
        io::write_png(o.out / it->second, frame);
      }
    });
  }
  data::encode_webm(frames_of(first.media[0]), o.max_frames, o.fps, o.out / broken.media[1],
                     [&](int index, io::ImageF& frame) { corrupt_frame(frame, index, o.seed); });
  for (const auto& [media, source] : style_images) {
    fs::create_directories((o.out / media).parent_path());
    fs::copy_file(source, o.out / media, fs::copy_options::overwrite_existing);
  }
  write_study(s);
  return s;
}

}  // namespace s4d::study
