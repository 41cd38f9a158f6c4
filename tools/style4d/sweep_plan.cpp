// style4d sweep plan: a sweep spec (JSON) -> SWEEP/manifest.json. Train each (dataset, preset) once,
// stylize it per (style, method), bench each stylized result. Errors are "SPEC: field: why".
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <regex>
#include <stdexcept>

#include "sweep.h"

namespace s4d::cli::sweep {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

struct SpecError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// "field.key", or "key" at the top level.
std::string at(const std::string& field, const std::string& key) { return field.empty() ? key : field + "." + key; }

class Spec {
 public:
  explicit Spec(fs::path file) : file_(std::move(file)) {
    std::ifstream in(file_);
    if (!in) throw std::runtime_error(file_.string() + ": cannot be read");
    try {
      j_ = json::parse(in);
    } catch (const json::exception& e) {
      throw std::runtime_error(file_.string() + ": not valid JSON (" + e.what() + ")");
    }
    if (!j_.is_object()) fail("", "expected a JSON object");
  }
  [[noreturn]] void fail(const std::string& field, const std::string& why) const {
    throw SpecError(file_.string() + ": " + (field.empty() ? "" : field + ": ") + why);
  }
  const json& root() const { return j_; }
  // A path in the spec, relative to the spec's folder.
  fs::path path(const std::string& text) const {
    const fs::path p(text);
    return fs::absolute(p.is_absolute() ? p : file_.parent_path() / p).lexically_normal();
  }
  std::string name(const json& parent, const std::string& key, const std::string& field) const {
    const std::string where = at(field, key);
    if (!parent.contains(key) || !parent[key].is_string()) fail(where, "expected a string");
    const std::string v = parent[key].get<std::string>();
    static const std::regex ok("[A-Za-z0-9_-]+");
    if (!std::regex_match(v, ok)) fail(where, "'" + v + "' must be letters, digits, '_' or '-' (it names files and cells)");
    return v;
  }
  std::string string_or(const json& parent, const std::string& key, const std::string& field, const std::string& fallback) const {
    if (!parent.contains(key)) return fallback;
    if (!parent[key].is_string()) fail(at(field, key), "expected a string");
    return parent[key].get<std::string>();
  }
  int int_or(const json& parent, const std::string& key, const std::string& field, int fallback, int lowest) const {
    if (!parent.contains(key) || parent[key].is_null()) return fallback;
    if (!parent[key].is_number_integer() || parent[key].get<int>() < lowest)
      fail(at(field, key), "expected an integer of at least " + std::to_string(lowest));
    return parent[key].get<int>();
  }
  std::vector<std::string> strings(const json& parent, const std::string& key, const std::string& field) const {
    if (!parent.contains(key)) return {};
    const json& a = parent[key];
    if (!a.is_array()) fail(at(field, key), "expected an array of strings");
    std::vector<std::string> out;
    for (const json& s : a) {
      if (!s.is_string()) fail(at(field, key), "expected an array of strings");
      out.push_back(s.get<std::string>());
    }
    return out;
  }
  const json& array(const std::string& key) const {
    if (!j_.contains(key) || !j_[key].is_array() || j_[key].empty()) fail(key, "expected a non-empty array");
    return j_[key];
  }
  const json& object(const json& parent, const std::string& key, const std::string& field) const {
    static const json empty = json::object();
    if (!parent.contains(key)) return empty;
    if (!parent[key].is_object()) fail(at(field, key), "expected an object");
    return parent[key];
  }

 private:
  fs::path file_;
  json j_;
};

// The file that marks each layout (ARCHITECTURE.md "data"; data::load_dataset detects the same).
void check_layout(const Spec& spec, const std::string& field, const std::string& layout, const fs::path& dir) {
  static const std::vector<std::pair<std::string, std::string>> markers = {
      {"dynerf", "poses_bounds.npy"}, {"dnerf", "transforms_train.json"}, {"hypernerf", "dataset.json"}, {"colmap", "sparse/0"}};
  if (layout == "auto") return;
  for (const auto& [name, marker] : markers) {
    if (name != layout) continue;
    if (fs::exists(dir) && !fs::exists(dir / marker))
      spec.fail(field, "'" + layout + "' but " + dir.string() + " has no " + marker);
    return;
  }
  spec.fail(field, "'" + layout + "': expected auto, dynerf, dnerf, hypernerf or colmap");
}

SlurmStage slurm_stage(const Spec& spec, const json& base, const json& over, const std::string& field) {
  json merged = base;
  for (const auto& [k, v] : over.items()) merged[k] = v;
  static const std::vector<std::string> known = {"time", "partition", "account", "mem", "gpus", "cpus_per_task", "max_parallel", "extra"};
  for (const auto& [k, v] : merged.items())
    if (std::find(known.begin(), known.end(), k) == known.end())
      spec.fail(field + "." + k, "unknown setting (time, partition, account, mem, gpus, cpus_per_task, max_parallel, extra)");
  SlurmStage s;
  s.time = spec.string_or(merged, "time", field, s.time);
  s.partition = spec.string_or(merged, "partition", field, "");
  s.account = spec.string_or(merged, "account", field, "");
  s.mem = spec.string_or(merged, "mem", field, "");
  s.gpus = spec.int_or(merged, "gpus", field, 0, 0);
  s.cpus_per_task = spec.int_or(merged, "cpus_per_task", field, 1, 1);
  s.max_parallel = spec.int_or(merged, "max_parallel", field, 0, 0);
  s.extra = spec.strings(merged, "extra", field);
  return s;
}

void append(std::vector<std::string>& to, const std::vector<std::string>& more) { to.insert(to.end(), more.begin(), more.end()); }

}  // namespace

Manifest plan(const fs::path& spec_file, const fs::path& out, const fs::path& program) {
  const Spec spec(spec_file);
  const json& j = spec.root();
  static const std::vector<std::string> known = {"name", "datasets", "presets", "train", "styles", "methods", "stylize", "bench", "env", "slurm"};
  for (const auto& [k, v] : j.items())
    if (std::find(known.begin(), known.end(), k) == known.end())
      spec.fail(k, "unknown field (name, datasets, presets, train, styles, methods, stylize, bench, env, slurm)");
  Manifest m;
  m.root = fs::absolute(out).lexically_normal();
  m.program = program;
  m.spec = fs::absolute(spec_file);
  m.name = j.contains("name") ? spec.name(j, "name", "") : m.root.filename().string();
  for (const auto& [k, v] : spec.object(j, "env", "").items()) {
    if (!v.is_string()) spec.fail("env." + k, "expected a string");
    m.env[k] = v.get<std::string>();
  }
  const json& slurm = spec.object(j, "slurm", "");
  for (const auto& [k, v] : slurm.items())
    if (k != "default" && k != "train" && k != "stylize" && k != "bench")
      spec.fail("slurm." + k, "expected default, train, stylize or bench");
  for (const char* stage : kStages)
    m.slurm[stage] = slurm_stage(spec, spec.object(slurm, "default", "slurm"), spec.object(slurm, stage, "slurm"), std::string("slurm.") + stage);

  std::vector<std::string> presets = spec.strings(j, "presets", "");
  if (presets.empty()) presets = {"default"};
  for (const std::string& p : presets)
    if (p != "fast" && p != "default" && p != "quality") spec.fail("presets", "'" + p + "': expected fast, default or quality");
  const json& train = spec.object(j, "train", "");
  const json& stylize = spec.object(j, "stylize", "");
  const json& bench = spec.object(j, "bench", "");

  struct Style { std::string name; fs::path image; };
  std::vector<Style> styles;
  const json& style_list = spec.array("styles");
  for (size_t i = 0; i < style_list.size(); ++i) {
    const std::string field = "styles[" + std::to_string(i) + "]";
    Style s{spec.name(style_list[i], "name", field), spec.path(spec.string_or(style_list[i], "image", field, ""))};
    if (!fs::is_regular_file(s.image)) spec.fail(field + ".image", s.image.string() + ": no such file");
    for (const Style& o : styles)
      if (o.name == s.name) spec.fail(field + ".name", "'" + s.name + "' is already a style's name");
    styles.push_back(s);
  }
  struct Method { std::string name; std::vector<std::string> args; };
  std::vector<Method> methods;
  const json& method_list = spec.array("methods");
  for (size_t i = 0; i < method_list.size(); ++i) {
    const std::string field = "methods[" + std::to_string(i) + "]";
    const json& mj = method_list[i];
    Method me{spec.name(mj, "name", field), {}};
    if (auto v = spec.string_or(mj, "stylizer", field, ""); !v.empty()) append(me.args, {"--stylizer", v});
    if (auto v = spec.string_or(mj, "method", field, ""); !v.empty()) append(me.args, {"--method", v});
    if (auto v = spec.string_or(mj, "weights", field, ""); !v.empty()) append(me.args, {"--weights", spec.path(v).string()});
    append(me.args, spec.strings(mj, "args", field));
    for (const Method& o : methods)
      if (o.name == me.name) spec.fail(field + ".name", "'" + me.name + "' is already a method's name");
    methods.push_back(me);
  }

  const json& datasets = spec.array("datasets");
  std::vector<Cell> trains, stylizes, benches;
  for (size_t i = 0; i < datasets.size(); ++i) {
    const std::string field = "datasets[" + std::to_string(i) + "]";
    const json& d = datasets[i];
    const std::string scene = spec.name(d, "name", field);
    const fs::path data = spec.path(spec.string_or(d, "path", field, ""));
    if (!d.contains("path")) spec.fail(field + ".path", "expected the dataset folder");
    check_layout(spec, field + ".layout", spec.string_or(d, "layout", field, "auto"), data);
    const int downscale = spec.int_or(d, "downscale", field, 1, 1);
    for (const Cell& t : trains)
      if (t.scene == scene) spec.fail(field + ".name", "'" + scene + "' is already a dataset's name");
    for (const std::string& preset : presets) {
      const std::string key = scene + "." + preset;
      const fs::path run = m.root / "runs" / key;
      Cell t;
      t.id = "train." + key, t.stage = "train", t.scene = scene, t.preset = preset;
      t.command = {"train", "--data", data.string(), "--run", run.string(), "--preset", preset, "--downscale", std::to_string(downscale)};
      if (int n = spec.int_or(train, "iters", "train", 0, 1)) append(t.command, {"--iters", std::to_string(n)});
      if (int n = spec.int_or(train, "fine_iters", "train", 0, 1)) append(t.command, {"--fine-iters", std::to_string(n)});
      append(t.command, spec.strings(train, "args", "train"));
      append(t.command, spec.strings(d, "train_args", field));
      t.resume_when = (run / "run.json").string();
      t.resume_command = {"train", "--run", run.string()};
      t.clean = {run.string()};
      t.outputs = {(run / "train.json").string()};
      for (const Style& s : styles)
        for (const Method& me : methods) {
          const std::string name = s.name + "." + me.name, cell = key + "." + name;
          Cell st;
          st.id = "stylize." + cell, st.stage = "stylize", st.scene = scene, st.preset = preset, st.style = s.name, st.method = me.name;
          st.after = {t.id};
          st.command = {"stylize", "--run", run.string(), "--style-image", s.image.string(), "--style", name};
          append(st.command, me.args);
          append(st.command, spec.strings(stylize, "args", "stylize"));
          // A killed stylize continues from its checkpoint when given the same command again.
          st.resume_when = (run / "style" / name / "checkpoint.s4dckpt").string();
          st.resume_command = st.command;
          st.outputs = {(run / "style" / name / "stylize.json").string()};
          Cell b;
          const fs::path report = m.root / "bench" / cell;
          b.id = "bench." + cell, b.stage = "bench", b.scene = scene, b.preset = preset, b.style = s.name, b.method = me.name;
          b.after = {st.id};
          b.command = {"bench", "--run", run.string(), "--style", name, "--scene", scene, "--out", report.string()};
          append(b.command, spec.strings(bench, "args", "bench"));
          b.clean = {report.string()};
          b.outputs = {(report / "report.json").string()};
          stylizes.push_back(st);
          benches.push_back(b);
        }
      trains.push_back(t);
    }
  }
  for (auto* list : {&trains, &stylizes, &benches}) m.cells.insert(m.cells.end(), list->begin(), list->end());
  return m;
}

}  // namespace s4d::cli::sweep
