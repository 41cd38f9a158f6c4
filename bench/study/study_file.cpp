#include "s4d/study/study_file.h"

#include <fstream>
#include <sstream>
#include <stdexcept>

#include "s4d/util/atomic_file.h"

namespace s4d::study {

namespace {

namespace fs = std::filesystem;

// A field of a study.json object, named in the error as where.field.
template <class T>
T field(const nlohmann::json& j, const char* name, const fs::path& file, const std::string& where) {
  if (!j.is_object() || !j.contains(name))
    throw std::runtime_error(file.string() + ": " + where + "." + name + ": missing");
  try {
    return j.at(name).get<T>();
  } catch (const nlohmann::json::exception&) {
    throw std::runtime_error(file.string() + ": " + where + "." + name + ": wrong type (" + j.at(name).dump() + ")");
  }
}

}  // namespace

const std::vector<Criterion>& video_criteria() {
  static const std::vector<Criterion> c = {
      {"stylization", "Which video carries the style of the style image better?"},
      {"consistency", "Which video is more consistent over time and across viewpoints (less flicker, fewer jumps)?"},
      {"video_quality", "Which video looks better overall, as a video?"},
  };
  return c;
}

const std::vector<Criterion>& frame_criteria() {
  static const std::vector<Criterion> c = {
      {"stylization", "Which image carries the style of the style image better?"},
      {"image_quality", "Which image looks better (sharper, fewer artefacts)?"},
  };
  return c;
}

const Item& Study::item(const std::string& id) const {
  for (const Item& i : items)
    if (i.id == id) return i;
  throw std::invalid_argument((root / "study.json").string() + ": no item '" + id + "'");
}

const Participant* Study::participant(const std::string& code) const {
  for (const Participant& p : participants)
    if (p.code == code) return &p;
  return nullptr;
}

nlohmann::json to_json(const Study& s) {
  nlohmann::json criteria = nlohmann::json::object();
  for (const char* kind : {"video", "frame"}) {
    nlohmann::json list = nlohmann::json::array();
    for (const Criterion& c : std::string(kind) == "video" ? video_criteria() : frame_criteria())
      list.push_back({{"id", c.id}, {"question", c.question}});
    criteria[kind] = list;
  }
  nlohmann::json parts = nlohmann::json::array(), items = nlohmann::json::array(), people = nlohmann::json::array();
  for (const Part& p : s.parts) parts.push_back({{"id", p.id}, {"title", p.title}});
  for (const Item& i : s.items)
    items.push_back({{"id", i.id}, {"part", i.part}, {"kind", i.kind}, {"scene", i.scene}, {"style", i.style},
                     {"view", i.view}, {"methods", {i.methods[0], i.methods[1]}}, {"media", {i.media[0], i.media[1]}},
                     {"style_image", i.style_image}, {"check", i.check}, {"intact", i.intact}});
  for (const Participant& p : s.participants) {
    nlohmann::json order = nlohmann::json::array();
    for (const Placement& o : p.order) order.push_back({{"item", o.item}, {"swap", o.swap}});
    people.push_back({{"code", p.code}, {"order", order}});
  }
  // The criteria are written for people reading the file; the program takes them from the kind.
  return {{"format", kFormat}, {"seed", s.seed}, {"fps", s.fps}, {"criteria", criteria},
          {"parts", parts}, {"items", items}, {"participants", people}};
}

Study read_study(const fs::path& study_dir) {
  const fs::path file = study_dir / "study.json";
  std::ifstream in(file);
  if (!in) throw std::runtime_error(file.string() + ": cannot read (not a study folder? `style4d study plan` writes it)");
  std::stringstream text;
  text << in.rdbuf();
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text.str());
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(file.string() + ": not JSON: " + e.what());
  }
  if (field<std::string>(j, "format", file, "study") != kFormat)
    throw std::runtime_error(file.string() + ": format: expected " + kFormat + ", got " + j.at("format").dump());
  Study s;
  s.root = study_dir;
  s.seed = field<uint64_t>(j, "seed", file, "study");
  s.fps = field<double>(j, "fps", file, "study");
  for (const auto& p : field<nlohmann::json>(j, "parts", file, "study"))
    s.parts.push_back({field<std::string>(p, "id", file, "parts[]"), field<std::string>(p, "title", file, "parts[]")});
  for (const auto& i : field<nlohmann::json>(j, "items", file, "study")) {
    Item it;
    it.id = field<std::string>(i, "id", file, "items[]");
    const std::string where = "items[" + it.id + "]";
    it.part = field<std::string>(i, "part", file, where);
    it.kind = field<std::string>(i, "kind", file, where);
    if (it.kind != "video" && it.kind != "frame")
      throw std::runtime_error(file.string() + ": " + where + ".kind: expected video or frame, got '" + it.kind + "'");
    it.scene = field<std::string>(i, "scene", file, where);
    it.style = field<std::string>(i, "style", file, where);
    it.view = field<std::string>(i, "view", file, where);
    const auto methods = field<std::vector<std::string>>(i, "methods", file, where);
    const auto media = field<std::vector<std::string>>(i, "media", file, where);
    if (methods.size() != 2 || media.size() != 2)
      throw std::runtime_error(file.string() + ": " + where + ": methods and media need two entries each");
    for (int k = 0; k < 2; ++k) it.methods[k] = methods[k], it.media[k] = media[k];
    it.style_image = field<std::string>(i, "style_image", file, where);
    it.check = field<std::string>(i, "check", file, where);
    if (it.check != "" && it.check != "identical" && it.check != "broken")
      throw std::runtime_error(file.string() + ": " + where + ".check: expected \"\", identical or broken");
    it.intact = field<int>(i, "intact", file, where);
    s.items.push_back(std::move(it));
  }
  for (const auto& p : field<nlohmann::json>(j, "participants", file, "study")) {
    Participant person{field<std::string>(p, "code", file, "participants[]"), {}};
    for (const auto& o : field<nlohmann::json>(p, "order", file, "participants[" + person.code + "]")) {
      Placement placement{field<std::string>(o, "item", file, "order[]"), field<bool>(o, "swap", file, "order[]")};
      s.item(placement.item);  // an order naming no item is refused here, not at a participant's vote
      person.order.push_back(placement);
    }
    s.participants.push_back(std::move(person));
  }
  return s;
}

void write_study(const Study& s) { util::write_file_atomic(s.root / "study.json", to_json(s).dump(1) + "\n"); }

}  // namespace s4d::study
