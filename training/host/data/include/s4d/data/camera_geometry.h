// Geometry of a dataset's cameras that loaders, the dataset check and initialisation share: where a
// camera is, where a point lies in its frame, and the point the cameras look at.
#pragma once
#include <optional>
#include <vector>

#include "s4d/io/nerf_cameras.h"
#include "s4d/util/vec3.h"

namespace s4d::data {

// Camera centre -R^T t of the row-major world-to-camera [R | t].
Vec3 camera_centre(const io::CameraView& camera);

// World point p in the camera's frame (OpenCV axes: z forward).
Vec3 to_camera(const io::CameraView& camera, const Vec3& p);

// Whether the camera sees p: in front of it and inside its image.
bool sees(const io::CameraView& camera, const Vec3& p);

// The point nearest (least squares) to the cameras' optical axes: solves
// sum (I - d d^T) p = sum (I - d d^T) c. nullopt when the axes are (nearly) parallel.
std::optional<Vec3> nearest_to_optical_axes(const std::vector<const io::CameraView*>& cameras);

}  // namespace s4d::data
