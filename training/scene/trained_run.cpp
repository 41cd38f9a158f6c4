#include "s4d/scene/trained_run.h"

#include <nlohmann/json.hpp>

#include <fstream>
#include <stdexcept>

#include "s4d/io/ply_gaussians.h"
#include "s4d/scene/static_scene.h"
#include "s4d/train/run_dir.h"
#include "s4d/train/train_config.h"

namespace s4d::scene {
namespace {

namespace fs = std::filesystem;

nlohmann::json read_run_json(const train::RunDir& run) {
  if (!fs::is_directory(run.root)) throw std::runtime_error(run.root.string() + ": no such run directory");
  std::ifstream in(run.run_json());
  if (!in)
    throw std::runtime_error(run.run_json().string() + ": missing; " + run.root.string() +
                             " is not a training run (make one with style4d train)");
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(run.run_json().string() + ": " + e.what());
  }
}

const nlohmann::json& field(const nlohmann::json& j, const char* key, const char* what, const fs::path& file) {
  if (!j.is_object() || !j.contains(key))
    throw std::runtime_error(file.string() + ": no field '" + key + "' (" + what + ")");
  return j.at(key);
}

}  // namespace

TrainedRun open_trained_run(engine::Context& ctx, const fs::path& run_dir, const std::optional<std::string>& style) {
  const train::RunDir run{run_dir};
  const nlohmann::json j = read_run_json(run);
  const nlohmann::json& data = field(j, "data", "the dataset path", run.run_json());
  const nlohmann::json& settings = field(j, "settings", "the training settings", run.run_json());
  if (!data.is_string()) throw std::runtime_error(run.run_json().string() + ": field 'data' is not a string");
  train::TrainConfig config;
  try {
    config = train::config_from_json(settings);
  } catch (const std::exception& e) {
    throw std::runtime_error(run.run_json().string() + ": field 'settings': " + e.what());
  }
  if (!fs::exists(run.gaussians_ply()))
    throw std::runtime_error(run.gaussians_ply().string() + ": missing; the run has not written its Gaussians yet "
                             "(style4d train writes them at each checkpoint and at the end)");
  if (style)
    throw std::runtime_error("no style " + *style + " in " + run_dir.string() +
                             " (styles are trained with style4d stylize, not built yet)");
  const fs::path data_path = data.get<std::string>();
  if (!fs::exists(data_path))
    throw std::runtime_error(run.run_json().string() + ": field 'data' names " + data_path.string() +
                             ", which does not exist");

  if (j.contains("stage") && !j.at("stage").is_string())
    throw std::runtime_error(run.run_json().string() + ": field 'stage' is not a string");
  const std::string stage = j.value("stage", "static");  // runs written before stages were named
  if (stage != "static")
    throw std::runtime_error(run.run_json().string() + ": stage '" + stage +
                             "' is not one this build renders (static; rendering 4DGS runs is not built yet)");
  TrainedRun out;
  out.root = run_dir;
  out.stage = stage;
  out.dataset = data::load_dataset(data_path, {.downscale = config.downscale, .background = config.background});
  out.scene = std::make_unique<StaticScene>(ctx, io::read_ply_gaussians(run.gaussians_ply()), "run gaussians");
  return out;
}

}  // namespace s4d::scene
