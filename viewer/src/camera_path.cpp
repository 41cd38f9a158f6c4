#include "s4d/viewer/camera_path.h"

#include <cstdio>
#include <stdexcept>

namespace s4d::viewer {

void CameraPath::add(const CameraControl& control, uint32_t width, uint32_t height, double time) {
  char name[32];
  std::snprintf(name, sizeof(name), "path_%04zu", views_.size());
  views_.push_back(control.view(width, height, name, time));
}

void CameraPath::write(const std::filesystem::path& path) {
  if (views_.empty()) throw std::logic_error("camera path " + path.string() + ": nothing was recorded");
  if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path());
  io::write_nerf_cameras(path, views_);
  views_.clear();
}

}  // namespace s4d::viewer
