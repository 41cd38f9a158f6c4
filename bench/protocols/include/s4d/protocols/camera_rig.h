// The spiral protocol's trajectory, designed from the training cameras.
//
// Rig analysis (training views; one per physical camera):
//   centre   the point nearest to all optical axes in the least-squares sense,
//            sum_i (I - d_i d_i^T) p = sum_i (I - d_i d_i^T) c_i  (c_i camera centre, d_i unit axis).
//            When the axes are (nearly) parallel the system is singular (det below 1e-6 of its scale)
//            and the centre falls back to the mean camera centre plus the mean axis times the
//            dataset's extent (or 1 when that is 0).
//   up       the normalised mean of the cameras' up vectors (-y of each camera).
//   facing   forward-facing when every camera's axis is within 60 degrees of the mean axis (Neu3D,
//            LLFF, the built-in synthetic arc); otherwise the rig surrounds the scene (D-NeRF).
//
// Forward-facing rigs: LLFF's render_path_spiral as 4DGaussians' get_spiral uses it for DyNeRF:
//   two turns, theta_k = 4 pi k / N, position = mean centre + r_x cos(theta) x + r_y sin(theta) y
//   + r_z sin(theta / 2) z in the mean camera's axes, where r_a is the 90th percentile of
//   |(c_i - mean centre) . a| (LLFF takes it of the uncentred positions; centring keeps the path on
//   the rig wherever the world origin is).
// Surrounding rigs: a helix, one turn, theta_k = 2 pi k / N starting at the first camera's azimuth,
//   radius = mean horizontal distance of the cameras from the centre, height rising linearly from the
//   lowest to the highest camera height above the centre (elevation clamped to +-60 degrees so the
//   view never looks straight down the up axis).
// Both: every frame looks at the centre with the rig's up, uses the first training camera's
// intrinsics and size, and frame k of N has time k / (N - 1) (0 for N = 1).
#pragma once
#include <array>
#include <vector>

#include "s4d/data/dataset.h"
#include "s4d/io/nerf_cameras.h"
#include "s4d/protocols/protocol.h"
#include "s4d/util/vec3.h"

namespace s4d::protocols {

struct RigSummary {
  Vec3 centre{};       // the point nearest to all optical axes
  Vec3 up{};           // unit
  Vec3 mean_centre{};  // mean camera position
  Vec3 mean_axis{};    // unit mean viewing direction
  bool forward_facing = false;
  std::vector<io::CameraView> cameras;  // one per physical training camera
};

// Throws std::invalid_argument when the dataset has no training view.
RigSummary analyse_rig(const data::Dataset& dataset);

// A world_to_cam (row-major 4x4, OpenCV axes) at `position` looking at `target` with `up` pointing up
// in the image. Throws std::invalid_argument when the view direction is parallel to `up`.
std::array<double, 16> look_at(const Vec3& position, const Vec3& target, const Vec3& up);

// The spiral's N frames (index, time, camera). Throws std::invalid_argument for frames < 1, or a
// forward-facing rig whose cameras all sit at one position (no spiral radius).
std::vector<ProtocolFrame> spiral_frames(const RigSummary& rig, int frames);

// Camera centre (-R^T t) and optical axis (third row of R) of a view.
Vec3 camera_centre(const io::CameraView& view);
Vec3 camera_axis(const io::CameraView& view);

}  // namespace s4d::protocols
