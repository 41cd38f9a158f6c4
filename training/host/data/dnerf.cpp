// D-NeRF layout: transforms_train.json, transforms_test.json and optionally transforms_val.json, each
// a NeRF transforms file (io::read_nerf_cameras) whose frames carry a 'time' in [0, 1]. file_path is
// relative to the root, with ".png" appended when it has no extension (how D-NeRF writes it). The
// files give camera_angle_x but no image size, so the size of each file's first image is the default.
// Frames are RGBA; FrameCache composites them on the background (white by default, as D-NeRF). The
// optional point cloud is points3D.ply or fused.ply.
#include <fstream>
#include <nlohmann/json.hpp>

#include "dataset_parts.h"

namespace s4d::data {
namespace {

namespace fs = std::filesystem;
using detail::fail;

fs::path image_path(const fs::path& root, const std::string& file_path) {
  fs::path p = root / file_path;
  if (!p.has_extension()) p += ".png";
  return p.lexically_normal();
}

// A frame's image must lie inside the dataset folder: an absolute file_path or one that climbs out
// ("../../etc/passwd") is refused rather than followed, and the file must exist.
fs::path checked_image_path(const fs::path& root, const fs::path& json_path, const std::string& field,
                            const std::string& file_path) {
  const fs::path relative = fs::path(file_path).lexically_normal();
  if (fs::path(file_path).is_absolute() || relative.empty() || *relative.begin() == "..")
    fail(json_path, field + ": '" + file_path + "' is not inside the dataset folder");
  const fs::path image = image_path(root, file_path);
  if (!fs::is_regular_file(image)) fail(json_path, field + ": image " + image.string() + " does not exist");
  return image;
}

// The size of the image that frames[0] names, when that can be found; read_nerf_cameras reports
// any problem with the file itself, and the frame cache any missing image.
std::optional<std::pair<int, int>> first_image_size(const fs::path& root, const fs::path& json_path) {
  std::ifstream in(json_path);
  const nlohmann::json j = nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/false);
  if (!j.is_object() || !j.contains("frames") || !j["frames"].is_array() || j["frames"].empty()) return std::nullopt;
  const nlohmann::json& first = j["frames"][0];
  if (!first.is_object() || !first.contains("file_path") || !first["file_path"].is_string()) return std::nullopt;
  return detail::png_size(checked_image_path(root, json_path, "frames[0].file_path", first["file_path"].get<std::string>()));
}

void add_split(Dataset& dataset, const fs::path& json_path, bool test, int factor) {
  const std::vector<io::CameraView> cameras = io::read_nerf_cameras(json_path, first_image_size(dataset.root, json_path));
  for (size_t i = 0; i < cameras.size(); ++i) {
    const std::string field = "frames[" + std::to_string(i) + "].time";
    if (!cameras[i].time) fail(json_path, field + ": missing (D-NeRF needs a time per frame)");
    View view;
    view.image = checked_image_path(dataset.root, json_path, "frames[" + std::to_string(i) + "].file_path", cameras[i].file_path);
    view.name = fs::relative(view.image, dataset.root).replace_extension().generic_string();
    view.camera = cameras[i];
    detail::downscale_camera(view.camera, factor);
    view.time = *cameras[i].time;
    view.test = test;
    dataset.views.push_back(std::move(view));
  }
}

}  // namespace

Dataset load_dnerf(const fs::path& root, const LoadOptions& options) {
  const int factor = detail::checked_downscale(root, options);
  Dataset dataset;
  dataset.kind = "dnerf";
  dataset.layout = "dnerf";
  dataset.root = root;
  for (const char* name : {"transforms_train.json", "transforms_test.json"}) {
    if (!fs::exists(root / name)) fail(root / name, "missing (a D-NeRF dataset needs it)");
  }
  add_split(dataset, root / "transforms_train.json", false, factor);
  // Validation views are held out too; their names start with their folder ("val/...").
  if (fs::exists(root / "transforms_val.json")) add_split(dataset, root / "transforms_val.json", true, factor);
  add_split(dataset, root / "transforms_test.json", true, factor);
  detail::finish_dataset(dataset, options, {1.0f, 1.0f, 1.0f}, {"points3D.ply", "fused.ply"});
  return dataset;
}

}  // namespace s4d::data
