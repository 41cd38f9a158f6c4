// Path parsing and the fixed-camera protocols (test, train:CAM); the spiral is in camera_rig.cpp.
#include "s4d/protocols/protocol.h"

#include <algorithm>
#include <map>
#include <set>
#include <stdexcept>

#include "s4d/protocols/camera_rig.h"

namespace s4d::protocols {
namespace {

// One sequence per physical camera of the chosen split, in dataset order: the camera of its first
// view and the sorted distinct times of `time_views` (the camera's own views, or all views of the
// split when each view has its own camera).
std::vector<Sequence> fixed_camera_sequences(const data::Dataset& dataset, bool test, const std::string* only) {
  std::vector<std::string> order;
  std::map<std::string, io::CameraView> camera;
  std::map<std::string, std::set<double>> times;
  std::set<double> split_times;
  bool per_view_cameras = false;
  for (const data::View& v : dataset.views) {
    if (v.test != test) continue;
    const std::string name = camera_name(v);
    if (camera.emplace(name, v.camera).second) order.push_back(name);
    times[name].insert(v.time);
    split_times.insert(v.time);
    per_view_cameras = per_view_cameras || v.camera_index < 0;
  }
  if (only != nullptr && camera.count(*only) == 0) {
    std::string names;
    for (size_t k = 0; k < order.size() && k < 12; ++k) names += (k ? ", " : "") + order[k];
    if (order.size() > 12) names += ", ... (" + std::to_string(order.size()) + " in all)";
    throw std::invalid_argument("train:" + *only + ": no training camera named '" + *only + "' in " +
                                dataset.root.string() + "; the training cameras are " + names);
  }
  std::vector<Sequence> out;
  for (const std::string& name : order) {
    if (only != nullptr && name != *only) continue;
    Sequence s{name, {}};
    for (double t : per_view_cameras ? split_times : times[name]) {
      ProtocolFrame f;
      f.index = static_cast<int>(s.frames.size());
      f.time = t;
      f.camera = camera[name];
      f.camera.name = name;
      f.camera.time = t;
      s.frames.push_back(std::move(f));
    }
    out.push_back(std::move(s));
  }
  return out;
}

// A camera path file's frames in file order, each at its own time.
Sequence camera_path_sequence(const std::filesystem::path& file) {
  const std::vector<io::CameraView> views = io::read_nerf_cameras(file);
  if (views.empty()) throw std::runtime_error(file.string() + ": frames: empty; a camera path needs at least one frame");
  Sequence s{file.stem().string(), {}};
  for (const io::CameraView& v : views) {
    if (!v.time)
      throw std::runtime_error(file.string() + ": frames[" + std::to_string(s.frames.size()) + "] (" + v.name +
                               "): no 'time'; each frame of a camera path gives its time in [0, 1]");
    s.frames.push_back({static_cast<int>(s.frames.size()), *v.time, v});
  }
  return s;
}

}  // namespace

std::string PathSpec::text() const {
  switch (kind) {
    case Kind::test: return "test";
    case Kind::spiral: return "spiral";
    case Kind::file: return file.string();
    case Kind::train: break;
  }
  return "train:" + camera;
}

PathSpec parse_path(const std::string& text) {
  if (text == "test") return {PathSpec::Kind::test, {}, {}};
  if (text == "spiral") return {PathSpec::Kind::spiral, {}, {}};
  if (text.rfind("train:", 0) == 0 && text.size() > 6) return {PathSpec::Kind::train, text.substr(6), {}};
  if (text.size() > 5 && text.ends_with(".json")) return {PathSpec::Kind::file, {}, text};
  throw std::invalid_argument("--path: expected test, spiral, train:CAM (a training camera name such as train:cam01) or a "
                              "camera path FILE.json, got '" + text + "'");
}

std::string camera_name(const data::View& view) {
  if (view.camera_index >= 0) return view.name.substr(0, view.name.find('/'));
  std::string name = view.name;
  std::replace(name.begin(), name.end(), '/', '_');
  return name;
}

std::vector<Sequence> build_protocol(const data::Dataset& dataset, const PathSpec& path, int spiral_frames_count) {
  switch (path.kind) {
    case PathSpec::Kind::test: {
      std::vector<Sequence> s = fixed_camera_sequences(dataset, true, nullptr);
      if (s.empty()) throw std::invalid_argument("--path test: " + dataset.root.string() + " has no test views");
      return s;
    }
    case PathSpec::Kind::spiral: return {Sequence{"spiral", spiral_frames(analyse_rig(dataset), spiral_frames_count)}};
    case PathSpec::Kind::file: return {camera_path_sequence(path.file)};
    case PathSpec::Kind::train: break;
  }
  return fixed_camera_sequences(dataset, false, &path.camera);
}

}  // namespace s4d::protocols
