// Private pieces shared by the layout loaders: the "<file>: <problem>" error convention, PNG size
// probing, intrinsics downscaling and the scene-level fields every layout fills the same way.
#pragma once
#include <filesystem>
#include <string>
#include <utility>

#include "s4d/data/dataset.h"

namespace s4d::data::detail {

// Throws std::runtime_error("<path>: <what>").
[[noreturn]] void fail(const std::filesystem::path& path, const std::string& what);

// (width, height) from a PNG's IHDR chunk, without decoding the image.
std::pair<int, int> png_size(const std::filesystem::path& path);

// Image size after the box filter: trailing rows and columns that do not fill a whole block are dropped.
inline int downscaled(int size, int factor) { return size / factor; }

// Rescales intrinsics to the box-filtered image. Output pixel I covers input pixels [f I, f I + f),
// whose centre f (I + 0.5) is input coordinate u, so u_out = u_in / f: every intrinsic divides by f.
void downscale_camera(io::CameraView& camera, int factor);

// options.downscale, checked to be >= 1 (the error names the dataset root).
int checked_downscale(const std::filesystem::path& root, const LoadOptions& options);

// Fills downscale, background (the layout default when unset), extent and the optional points3D.ply
// point cloud. Views must already be loaded.
void finish_dataset(Dataset& dataset, const LoadOptions& options, const std::array<float, 3>& default_background);

// Reads x, y, z (float) and red, green, blue (uchar) of every vertex of a PLY file (binary little
// endian or ASCII) into [P * 3] positions and [P * 3] colours in [0, 1].
void read_point_cloud(const std::filesystem::path& path, std::vector<float>& points, std::vector<float>& colors);

}  // namespace s4d::data::detail
