// Writes tiny HyperNeRF / Nerfies datasets for the loader tests, straight from the layout's public
// conventions (google/hypernerf camera.py and datasets/nerfies.py), not through the loader's code:
// camera/ID.json holds `orientation`, the world-to-camera rotation (its rows are the camera's x right,
// y down, z forward axes in world), and `position`, the camera centre, both in the raw world frame
// that scene.json's center and scale normalise.
#pragma once
#include <cmath>
#include <filesystem>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "data_test_util.h"

namespace s4d::test {

// One JSON object as key -> the JSON text of its value, so a test can replace any field.
using JsonFields = std::map<std::string, std::string>;

inline std::string json_number(double v) {
  std::ostringstream s;
  s.precision(17);  // round-trips every double
  s << v;
  return s.str();
}

inline std::string json_array(const std::vector<double>& values) {
  std::string out = "[";
  for (size_t i = 0; i < values.size(); ++i) out += (i ? ", " : "") + json_number(values[i]);
  return out + "]";
}

inline std::string json_object(const JsonFields& fields) {
  std::string out = "{";
  for (const auto& [key, value] : fields) out += (out.size() > 1 ? ", \"" : "\"") + key + "\": " + value;
  return out + "}";
}

inline std::string json_string(const std::string& s) { return "\"" + s + "\""; }

// The fields of camera/ID.json for a view whose world_to_cam maps the raw world frame. With
// `transposed`, orientation is written camera-to-world (the wrong convention), for negative tests.
inline JsonFields hyper_camera_fields(const io::CameraView& c, bool transposed = false) {
  std::string rows = "[";
  for (size_t i = 0; i < 3; ++i) {
    std::vector<double> row;
    for (size_t k = 0; k < 3; ++k) row.push_back(transposed ? c.world_to_cam[k * 4 + i] : c.world_to_cam[i * 4 + k]);
    rows += (i ? ", " : "") + json_array(row);
  }
  const Vec3 position = centre(c);
  return {{"orientation", rows + "]"},
          {"position", json_array({position[0], position[1], position[2]})},
          {"focal_length", json_number(c.fx)},
          {"pixel_aspect_ratio", json_number(c.fy / c.fx)},
          {"principal_point", json_array({c.cx, c.cy})},
          {"skew", "0.0"},
          {"radial_distortion", "[0.0, 0.0, 0.0]"},
          {"tangential_distortion", "[0.0, 0.0]"},
          {"image_size", json_array({static_cast<double>(c.width), static_cast<double>(c.height)})}};
}

struct HyperItem {
  std::string id;
  io::CameraView camera;        // world_to_cam in the raw world frame, full-resolution intrinsics
  std::filesystem::path image;  // copied to rgb/1x/ID.png
  long long warp_id = 0;
  int camera_id = 0;
  bool test = false;  // listed in val_ids rather than train_ids
};

struct HyperScene {
  Vec3 center{0, 0, 0};
  double scale = 1;
};

// Writes dataset.json, metadata.json, scene.json, camera/ID.json and rgb/1x/ID.png for `items` in
// order. `interp`: val_ids empty and every id in train_ids, as HyperNeRF's interp captures.
inline void write_hypernerf(const std::filesystem::path& root, const std::vector<HyperItem>& items, const HyperScene& scene,
                            bool interp = false, bool transposed = false) {
  namespace fs = std::filesystem;
  fs::create_directories(root / "camera");
  fs::create_directories(root / "rgb" / "1x");
  std::string ids = "[", train = "[", val = "[";
  JsonFields metadata;
  for (const HyperItem& item : items) {
    const std::string quoted = json_string(item.id);
    ids += (ids.size() > 1 ? ", " : "") + quoted;
    std::string& split = item.test && !interp ? val : train;
    split += (split.size() > 1 ? ", " : "") + quoted;
    metadata[item.id] = json_object({{"warp_id", std::to_string(item.warp_id)},
                                     {"appearance_id", std::to_string(item.warp_id)},
                                     {"camera_id", std::to_string(item.camera_id)}});
    write_raw(root / "camera" / (item.id + ".json"), json_object(hyper_camera_fields(item.camera, transposed)));
    fs::copy_file(item.image, root / "rgb" / "1x" / (item.id + ".png"), fs::copy_options::overwrite_existing);
  }
  write_raw(root / "dataset.json", json_object({{"count", std::to_string(items.size())},
                                                {"num_exemplars", std::to_string(items.size())},
                                                {"ids", ids + "]"},
                                                {"train_ids", train + "]"},
                                                {"val_ids", val + "]"}}));
  write_raw(root / "metadata.json", json_object(metadata));
  write_raw(root / "scene.json", json_object({{"scale", json_number(scene.scale)},
                                              {"center", json_array({scene.center[0], scene.center[1], scene.center[2]})},
                                              {"near", "0.01"},
                                              {"far", "10.0"}}));
}

// Items for the views of a loaded reference dataset: id = name with '/' -> '_', warp_id = the frame
// index (time * (frames - 1)), camera_id = the DyNeRF camera (0 without one).
inline std::vector<HyperItem> hyper_items(const data::Dataset& reference, int frames) {
  std::vector<HyperItem> items;
  for (const data::View& v : reference.views) {
    HyperItem item;
    item.id = v.name;
    for (char& ch : item.id) ch = ch == '/' ? '_' : ch;
    item.camera = v.camera;
    item.image = v.image;
    item.warp_id = std::llround(v.time * (frames - 1));
    item.camera_id = v.camera_index < 0 ? 0 : v.camera_index;
    item.test = v.test;
    items.push_back(item);
  }
  return items;
}

}  // namespace s4d::test
