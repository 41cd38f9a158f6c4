#include "s4d/viewer/dataset_cameras.h"

#include <algorithm>
#include <set>
#include <string>

namespace s4d::viewer {
namespace {

constexpr double kFramesPerSecond = 30;  // DyNeRF / Neu3D capture rate; the clip plays at it

std::string physical_camera_name(const data::View& v) {
  return v.camera_index >= 0 ? v.name.substr(0, v.name.find('/')) : v.name;
}

}  // namespace

std::vector<io::CameraView> dataset_cameras(const data::Dataset& dataset) {
  std::vector<io::CameraView> cameras;
  std::set<std::string> seen;
  for (const data::View& v : dataset.views) {
    const std::string name = physical_camera_name(v);
    if (!seen.insert(name).second) continue;
    io::CameraView cam = v.camera;
    cam.name = name;
    cameras.push_back(cam);
  }
  return cameras;
}

double clip_seconds(const data::Dataset& dataset) {
  std::set<double> times;
  for (const data::View& v : dataset.views) times.insert(v.time);
  return std::max(1.0, static_cast<double>(times.size()) / kFramesPerSecond);
}

}  // namespace s4d::viewer
