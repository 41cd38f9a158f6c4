// Private pieces shared by the layout loaders: the "<file>: <problem>" error convention, PNG size
// probing, intrinsics downscaling and the scene-level fields every layout fills the same way.
#pragma once
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "s4d/data/dataset.h"

namespace s4d::data::detail {

// Throws std::runtime_error("<path>: <what>").
[[noreturn]] void fail(const std::filesystem::path& path, const std::string& what);

// (width, height) from a PNG's IHDR chunk, without decoding the image.
std::pair<int, int> png_size(const std::filesystem::path& path);

// "has 29 frames but cam00 has 30: missing 0017.png (frame 17 of cam00), ..." for two cameras'
// sorted frame files (the caller's error names the camera's folder): the counts, then which file names one has and the other lacks (the first few).
std::string frame_count_mismatch(const std::vector<std::filesystem::path>& frames,
                                 const std::string& reference_name, const std::vector<std::filesystem::path>& reference);

// Image size after the box filter: trailing rows and columns that do not fill a whole block are dropped.
inline int downscaled(int size, int factor) { return size / factor; }

// Rescales intrinsics to the box-filtered image. Output pixel I covers input pixels [f I, f I + f),
// whose centre f (I + 0.5) is input coordinate u, so u_out = u_in / f: every intrinsic divides by f.
void downscale_camera(io::CameraView& camera, int factor);

// Adds frame `frame` of `frame_count` of a synchronized rig's camera `camera_index` (camera 0 is held
// out, the Neu3D protocol): view name "<camera_name>/<frame_name>", time frame / (count - 1), the
// camera's file_path relative to the root. frame_in_file >= 0: `image` is a video.
void add_rig_view(Dataset& dataset, const io::CameraView& camera, int camera_index, const std::string& camera_name,
                  const std::string& frame_name, const std::filesystem::path& image, int frame_in_file, size_t frame,
                  size_t frame_count);

// options.downscale, checked to be >= 1 (the error names the dataset root).
int checked_downscale(const std::filesystem::path& root, const LoadOptions& options);

// Fills downscale, background (the layout default when unset), extent and the point cloud: the first of
// `point_files` (paths relative to the root, in order of preference) that exists is read with
// read_points. Views must already be loaded.
void finish_dataset(Dataset& dataset, const LoadOptions& options, const std::array<float, 3>& default_background,
                    const std::vector<std::filesystem::path>& point_files = {"points3D.ply"});

// What a few training frames say about the background: alpha present, or the uniform colour of the
// opaque frames' borders (background.cpp).
struct BackgroundProbe {
  bool alpha = false;
  std::optional<std::array<float, 3>> border;
  size_t frames = 0;
};
BackgroundProbe probe_background(const Dataset& dataset);

// Sets dataset.background and its source: --background when given (with a conflict noted when the
// frames' borders say otherwise), else the layout default for frames with alpha, else the borders'
// uniform colour, else the layout default.
void choose_background(Dataset& dataset, const LoadOptions& options, const std::array<float, 3>& layout_default);

// Reads an initial point cloud by its file name: *.ply (read_point_cloud), *.npy ([P, 3] positions,
// no colours), points3D.bin / points3D.txt (read_colmap_points). Colours default to mid grey.
void read_points(const std::filesystem::path& path, std::vector<float>& points, std::vector<float>& colors);

// Reads x, y, z (float or double) and, when present, red, green, blue (uchar) of every vertex of a
// PLY file (binary little endian or ASCII) into [P * 3] positions and [P * 3] colours in [0, 1].
void read_point_cloud(const std::filesystem::path& path, std::vector<float>& points, std::vector<float>& colors);

// COLMAP's points3D.bin or points3D.txt (colmap_model.cpp): positions and colours of every point.
void read_colmap_points(const std::filesystem::path& path, std::vector<float>& points, std::vector<float>& colors);

}  // namespace s4d::data::detail
