#include "s4d/viewer/run_scene.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <fstream>
#include <set>
#include <stdexcept>

#include "s4d/data/dataset.h"
#include "s4d/train/run_dir.h"
#include "s4d/train/train_config.h"

namespace s4d::viewer {

namespace fs = std::filesystem;

namespace {

constexpr double kFramesPerSecond = 30;  // DyNeRF / Neu3D capture rate; the clip plays at it

nlohmann::json read_json(const fs::path& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path.string() + ": cannot be opened");
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(path.string() + ": " + e.what());
  }
}

std::string physical_camera_name(const data::View& v) {
  return v.camera_index >= 0 ? v.name.substr(0, v.name.find('/')) : v.name;
}

}  // namespace

RunScene open_run(const fs::path& run_dir) {
  const train::RunDir run{run_dir};
  if (!fs::is_directory(run_dir))
    throw std::runtime_error(run_dir.string() + " is not a directory; train one with `style4d train --data DIR --out " +
                             run_dir.string() + "`");
  std::vector<std::string> missing;
  if (!fs::exists(run.run_json())) missing.push_back("run.json (what was trained from what)");
  if (!fs::exists(run.train_json())) missing.push_back("train.json (written when training finishes)");
  if (!fs::exists(run.gaussians_ply())) missing.push_back("geometry/gaussians.ply (written when training finishes)");
  RunScene scene;
  scene.root = run_dir;
  if (fs::exists(run.run_json())) {
    const nlohmann::json j = read_json(run.run_json());
    if (!j.contains("data") || !j["data"].is_string())
      throw std::runtime_error(run.run_json().string() + ": no \"data\" path");
    scene.dataset = j["data"].get<std::string>();
    scene.stage = j.value("stage", "static");
    if (!fs::is_directory(scene.dataset))
      missing.push_back("the dataset " + scene.dataset.string() + " that run.json names");
  }
  if (!missing.empty()) {
    std::string list;
    for (size_t i = 0; i < missing.size(); ++i) list += (i ? "; " : "") + missing[i];
    const std::string fix = fs::exists(run.run_json())
                                ? "finish it with `style4d train --resume " + run_dir.string() + "`"
                                : "train one with `style4d train --data DIR --out " + run_dir.string() + "`";
    throw std::runtime_error(run_dir.string() + " is an incomplete run: missing " + list + "; " + fix);
  }

  const nlohmann::json run_json = read_json(run.run_json());
  train::TrainConfig config;
  try {
    config = train::config_from_json(run_json.at("settings"));
  } catch (const std::exception& e) {
    throw std::runtime_error(run.run_json().string() + ": settings: " + e.what());
  }
  const nlohmann::json train_json = read_json(run.train_json());
  if (train_json.contains("test_psnr") && train_json["test_psnr"].is_number())
    scene.test_psnr = train_json["test_psnr"].get<double>();

  const data::Dataset dataset =
      data::load_dataset(scene.dataset, {.downscale = config.downscale, .background = config.background});
  scene.background = dataset.background;
  std::set<std::string> seen;
  std::set<double> times;
  for (const data::View& v : dataset.views) {
    times.insert(v.time);
    const std::string name = physical_camera_name(v);
    if (!seen.insert(name).second) continue;
    io::CameraView cam = v.camera;
    cam.name = name;
    scene.cameras.push_back(cam);
  }
  if (scene.cameras.empty()) throw std::runtime_error(scene.dataset.string() + ": the dataset has no views");
  scene.clip_seconds = std::max(1.0, static_cast<double>(times.size()) / kFramesPerSecond);
  scene.cloud = io::read_ply_gaussians(run.gaussians_ply());
  if (scene.cloud.size() == 0) throw std::runtime_error(run.gaussians_ply().string() + ": no Gaussians");
  return scene;
}

}  // namespace s4d::viewer
