// A recorded camera path: one NeRF camera view per recorded frame, written as a transforms.json
// that `style4d render --ply PLY --cameras FILE` replays.
#pragma once
#include <filesystem>
#include <vector>

#include "s4d/io/nerf_cameras.h"
#include "s4d/viewer/camera_control.h"

namespace s4d::viewer {

class CameraPath {
 public:
  // Appends the current view (width x height pixels, at `time`), named path_0000, path_0001, ...
  void add(const CameraControl& control, uint32_t width, uint32_t height, double time);
  size_t size() const { return views_.size(); }
  bool empty() const { return views_.empty(); }
  // Writes the views (io::write_nerf_cameras, atomic) and clears the path.
  void write(const std::filesystem::path& path);

 private:
  std::vector<io::CameraView> views_;
};

}  // namespace s4d::viewer
