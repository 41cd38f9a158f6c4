#include "s4d/run/run_json.h"

#include <fstream>
#include <stdexcept>
#include <string>

#include "s4d/util/atomic_file.h"

namespace s4d::run {

namespace fs = std::filesystem;

void write_run_json(const RunDir& run, const RunJson& r) {
  nlohmann::json j = {{"data", fs::absolute(r.data).string()}, {"dataset", r.dataset}, {"settings", to_json(r.settings)}};
  if (r.stage) j["stage"] = geometry_name(*r.stage);
  util::write_file_atomic(run.run_json(), j.dump(2) + "\n");
}

RunJson read_run_json(const RunDir& run) {
  const std::string where = run.run_json().string();
  std::ifstream in(run.run_json());
  if (!in) throw std::runtime_error(where + ": cannot be opened");
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(where + ": " + e.what());
  }
  if (!j.is_object())
    throw std::runtime_error(where + ": expected a JSON object with 'data' and 'settings', got a JSON " +
                             std::string(j.type_name()));
  if (!j.contains("data") || !j["data"].is_string())
    throw std::runtime_error(where + ": field 'data' (the dataset path) is missing or not a string");
  if (!j.contains("settings")) throw std::runtime_error(where + ": field 'settings' (the training settings) is missing");
  RunJson out;
  out.data = j["data"].get<std::string>();
  out.settings = config_from_json(j["settings"], where);  // validated: a hand-edited value is refused by name
  if (j.contains("stage")) {
    const nlohmann::json& stage = j["stage"];
    out.stage = stage.is_string() ? parse_geometry(stage.get<std::string>()) : std::nullopt;
    if (!out.stage)
      throw std::runtime_error(where + ": field 'stage' = " + stage.dump() +
                               ": expected \"static\" or \"4dgs\" (what the run's geometry is)");
  }
  if (j.contains("dataset")) out.dataset = j["dataset"];
  return out;
}

}  // namespace s4d::run
