// The viewer's camera: a pose moved by orbit, pan, zoom (mouse) and fly (keys), snapped to dataset
// cameras, with the field of view of the last camera snapped to. Pure CPU math, no window. Zero
// input leaves the pose unchanged bit for bit, so the viewer can tell a still view.
#pragma once
#include <array>
#include <string>
#include <vector>

#include "s4d/io/nerf_cameras.h"
#include "s4d/splat/rasterizer.h"
#include "s4d/util/vec3.h"

namespace s4d::viewer {

class CameraControl {
 public:
  // `up`: the world's up direction for orbiting (see estimate_up); `speed`: fly speed in world
  // units per second.
  CameraControl(const Vec3& up, double speed);

  // Takes the camera's pose and field of view; the orbit pivot lies `pivot_depth` ahead.
  void snap(const io::CameraView& camera, double pivot_depth);
  // Turns about the pivot: `yaw` about the up axis, `pitch` about the camera's right axis
  // (radians). Pitch stops short of looking straight along the up axis.
  void orbit(double yaw, double pitch);
  // Moves camera and pivot in the image plane by (dx, dy) pixels of a view `height` pixels tall,
  // so points at the pivot's depth follow the cursor.
  void pan(double dx, double dy, double height);
  // Moves towards the pivot by a factor 0.9 per step (negative: away).
  void zoom(double steps);
  // Moves camera and pivot along the camera's forward, right and up axes for `seconds`.
  void fly(double forward, double right, double up, double seconds);

  // The rasterizer camera for a view of width x height pixels: the snapped camera's vertical field
  // of view and aspect of pixels, principal point at the centre.
  splat::Camera camera(uint32_t width, uint32_t height) const;
  // The same as a NeRF camera view (for camera paths), with `name` and `time`.
  io::CameraView view(uint32_t width, uint32_t height, const std::string& name, double time) const;

  const Vec3& position() const { return position_; }
  const Vec3& pivot() const { return pivot_; }
  // Camera axes in world coordinates (OpenCV: x right, y down, z forward).
  const std::array<Vec3, 3>& axes() const { return axes_; }

 private:
  void rotate_about_pivot(const Vec3& axis, double angle);

  Vec3 up_;
  double speed_;
  std::array<Vec3, 3> axes_{};  // right, down, forward
  Vec3 position_{}, pivot_{};
  double focal_per_height_ = 1;  // fy / image height of the snapped camera
  double aspect_ = 1;            // fx / fy
};

// The world's up direction of a camera rig: the mean of the cameras' up axes (-y in OpenCV axes),
// normalised; (0, 0, 1) when they cancel.
Vec3 estimate_up(const std::vector<io::CameraView>& cameras);

// Median depth of `means` ([N*3]) in front of `camera`; `fallback` when none is in front.
double median_depth(const io::CameraView& camera, const std::vector<float>& means, double fallback);

}  // namespace s4d::viewer
