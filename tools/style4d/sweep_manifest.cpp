#include "sweep_manifest.h"

#include <fstream>
#include <stdexcept>

#include "args.h"
#include "s4d/util/atomic_file.h"

namespace s4d::cli::sweep {

namespace fs = std::filesystem;

namespace {

nlohmann::json slurm_json(const SlurmStage& s) {
  return {{"time", s.time}, {"partition", s.partition}, {"account", s.account}, {"mem", s.mem}, {"gpus", s.gpus},
          {"cpus_per_task", s.cpus_per_task}, {"max_parallel", s.max_parallel}, {"extra", s.extra}};
}

nlohmann::json read_json(const fs::path& file) {
  std::ifstream in(file);
  if (!in) throw std::runtime_error(file.string() + ": cannot be read");
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(file.string() + ": not valid JSON (" + e.what() + ")");
  }
}

}  // namespace

const Cell& Manifest::cell(const std::string& id) const {
  for (const Cell& c : cells)
    if (c.id == id) return c;
  throw UsageError("no cell '" + id + "' in " + (root / "manifest.json").string() + " (style4d sweep status lists them)");
}

std::vector<const Cell*> Manifest::stage_cells(const std::string& stage) const {
  std::vector<const Cell*> out;
  for (const Cell& c : cells)
    if (c.stage == stage) out.push_back(&c);
  return out;
}

nlohmann::json to_json(const Manifest& m) {
  nlohmann::json cells = nlohmann::json::array(), slurm = nlohmann::json::object();
  for (const Cell& c : m.cells) {
    nlohmann::json j = {{"id", c.id},           {"stage", c.stage},     {"scene", c.scene},     {"preset", c.preset},
                        {"style", c.style},     {"method", c.method},   {"after", c.after},     {"command", c.command},
                        {"clean", c.clean},     {"outputs", c.outputs}};
    if (!c.resume_when.empty()) j["resume"] = {{"when", c.resume_when}, {"command", c.resume_command}};
    cells.push_back(j);
  }
  for (const auto& [stage, s] : m.slurm) slurm[stage] = slurm_json(s);
  return {{"format", "style4d-sweep/1"}, {"name", m.name},   {"root", m.root.string()}, {"program", m.program.string()},
          {"spec", m.spec.string()},     {"env", m.env},     {"slurm", slurm},          {"cells", cells}};
}

Manifest manifest_from_json(const nlohmann::json& j, const fs::path& file) {
  try {
    if (j.value("format", "") != "style4d-sweep/1")
      throw std::runtime_error("format: expected \"style4d-sweep/1\" (written by style4d sweep plan)");
    Manifest m;
    m.name = j.at("name").get<std::string>();
    m.root = j.at("root").get<std::string>();
    m.program = j.at("program").get<std::string>();
    m.spec = j.at("spec").get<std::string>();
    m.env = j.at("env").get<std::map<std::string, std::string>>();
    for (const auto& [stage, s] : j.at("slurm").items()) {
      SlurmStage st;
      st.time = s.at("time").get<std::string>();
      st.partition = s.at("partition").get<std::string>();
      st.account = s.at("account").get<std::string>();
      st.mem = s.at("mem").get<std::string>();
      st.gpus = s.at("gpus").get<int>();
      st.cpus_per_task = s.at("cpus_per_task").get<int>();
      st.max_parallel = s.at("max_parallel").get<int>();
      st.extra = s.at("extra").get<std::vector<std::string>>();
      m.slurm[stage] = st;
    }
    for (const auto& c : j.at("cells")) {
      Cell cell;
      cell.id = c.at("id").get<std::string>();
      cell.stage = c.at("stage").get<std::string>();
      cell.scene = c.at("scene").get<std::string>();
      cell.preset = c.at("preset").get<std::string>();
      cell.style = c.at("style").get<std::string>();
      cell.method = c.at("method").get<std::string>();
      cell.after = c.at("after").get<std::vector<std::string>>();
      cell.command = c.at("command").get<std::vector<std::string>>();
      cell.clean = c.at("clean").get<std::vector<std::string>>();
      cell.outputs = c.at("outputs").get<std::vector<std::string>>();
      if (c.contains("resume")) {
        cell.resume_when = c["resume"].at("when").get<std::string>();
        cell.resume_command = c["resume"].at("command").get<std::vector<std::string>>();
      }
      m.cells.push_back(std::move(cell));
    }
    return m;
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(file.string() + ": not a sweep manifest (" + e.what() + ")");
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(file.string() + ": " + e.what());
  }
}

Manifest read_manifest(const fs::path& sweep_dir) {
  const fs::path file = sweep_dir / "manifest.json";
  if (!fs::exists(file)) throw std::runtime_error(file.string() + ": missing; plan the sweep first (style4d sweep plan SPEC --out " +
                                                  sweep_dir.string() + ")");
  return manifest_from_json(read_json(file), file);
}

void write_manifest(const Manifest& m) {
  fs::create_directories(m.root);
  util::write_file_atomic(m.root / "manifest.json", to_json(m).dump(2) + "\n");
}

fs::path cell_dir(const Manifest& m, const std::string& id) { return m.root / "cells" / id; }

nlohmann::json read_state(const Manifest& m, const std::string& id) {
  const fs::path file = cell_dir(m, id) / "state.json";
  if (!fs::exists(file)) return nullptr;
  return read_json(file);
}

void write_state(const Manifest& m, const std::string& id, const nlohmann::json& state) {
  fs::create_directories(cell_dir(m, id));
  util::write_file_atomic(cell_dir(m, id) / "state.json", state.dump(2) + "\n");
}

bool cell_done(const Manifest& m, const Cell& c) {
  const nlohmann::json s = read_state(m, c.id);
  if (s.is_null() || s.value("state", "") != "done") return false;
  for (const std::string& o : c.outputs)
    if (!fs::exists(o)) return false;
  return true;
}

std::string cell_state(const Manifest& m, const Cell& c) {
  const nlohmann::json s = read_state(m, c.id);
  if (s.is_null()) return "not started";
  const std::string state = s.value("state", "not started");
  if (state == "done" && !cell_done(m, c)) return "outputs missing";  // removed since: runs again
  return state;
}

}  // namespace s4d::cli::sweep
